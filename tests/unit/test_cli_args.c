/*
 * test_cli_args.c - the refract CLI's pure helpers, with no daemon and no network:
 * option scanning, vector/dims/number/timeout parsing, image format from an extension
 * or a Content-Type, volume byte sizes, image sizes read from PNG/JPEG/EXR headers,
 * librefract's URL joining and path-segment escaping; and for lights (issue 3) the flags
 * of `refract light set` and the light object they make, the reading of an irradiance
 * status document, and how its table and progress are printed; for uploads (issue 5)
 * the kind and name a file's name implies, raw sizes per sample type, detached NRRD
 * headers, and the transfer line of the progress display.
 *
 * Unit tests link only the server libraries, so the files under test are compiled
 * into this one directly; none of them uses libcurl (cJSON comes with refract_scene).
 */
#include <stdint.h>

#include "test.h"

#include "../../client/cli/cli_args.c"
#include "../../client/cli/cli_image.c"
#include "../../client/cli/cli_irradiance.c"
#include "../../client/cli/cli_light.c"
#include "../../client/cli/cli_progress.c"
#include "../../client/cli/cli_upload_plan.c"
#include "../../client/cli/cli_view.c"
#include "../../client/refract_say.c"
#include "../../client/refract_status.c"
#include "../../client/refract_url.c"
#include "../../client/refract_view_json.c"

static void vec3_parses_three_comma_separated_numbers(void)
{
    double v[3] = {0, 0, 0};
    char why[256] = "";

    CHECK(cli_parse_vec3("1,2,3", v, why, sizeof(why)));
    CHECK_NEAR(v[0], 1.0, 0);
    CHECK_NEAR(v[1], 2.0, 0);
    CHECK_NEAR(v[2], 3.0, 0);
    CHECK(cli_parse_vec3(" -1.5 , 0 ,4e2 ", v, why, sizeof(why)));
    CHECK_NEAR(v[0], -1.5, 0);
    CHECK_NEAR(v[1], 0.0, 0);
    CHECK_NEAR(v[2], 400.0, 0);
}

static void vec3_rejects_wrong_counts_and_non_finite_values(void)
{
    static const char *const bad[] = {"1,2",     "1,2,3,4", "1,,3",  "",      "a,b,c",
                                      "nan,0,0", "0,inf,0", "1;2;3", "1,2,3x"};
    double v[3];
    char why[256];

    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        why[0] = '\0';
        CHECK_MSG(!cli_parse_vec3(bad[i], v, why, sizeof(why)), "accepted \"%s\"", bad[i]);
        CHECK_CONTAINS(why, "0,0,4");
    }
    cli_parse_vec3("1,2", v, why, sizeof(why));
    CHECK_CONTAINS(why, "got \"1,2\"");
}

static void dims_parses_three_positive_integers(void)
{
    int d[3] = {0, 0, 0};
    char why[256];

    CHECK(cli_parse_dims("64,32,16", d, why, sizeof(why)));
    CHECK_INT(d[0], 64);
    CHECK_INT(d[1], 32);
    CHECK_INT(d[2], 16);
    CHECK(cli_parse_dims("1, 1 ,65536", d, why, sizeof(why)));
    CHECK_INT(d[2], CLI_DIM_MAX);
}

static void dims_rejects_zero_negative_fractional_and_oversized(void)
{
    static const char *const bad[] = {"0,1,1", "-4,4,4",     "1.5,2,2", "65537,1,1",
                                      "64,64", "64,64,64,1", "x,y,z",   "99999999999999999999,1,1"};
    int d[3];
    char why[256];

    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
        CHECK_MSG(!cli_parse_dims(bad[i], d, why, sizeof(why)), "accepted \"%s\"", bad[i]);
    cli_parse_dims("0,1,1", d, why, sizeof(why));
    CHECK_CONTAINS(why, "1..65536");
}

static void numbers_must_be_whole_strings_in_range(void)
{
    long n = 0;
    double x = 0;
    char why[256];

    CHECK(cli_parse_long("640", 1, 65536, &n, why, sizeof(why)));
    CHECK_INT(n, 640);
    CHECK(!cli_parse_long("0", 1, 65536, &n, why, sizeof(why)));
    CHECK_CONTAINS(why, "1..65536");
    CHECK(!cli_parse_long("64x", 1, 65536, &n, why, sizeof(why)));
    CHECK(!cli_parse_long("", 1, 65536, &n, why, sizeof(why)));
    CHECK(cli_parse_double("-1.25", &x, why, sizeof(why)));
    CHECK_NEAR(x, -1.25, 0);
    CHECK(!cli_parse_double("1e999", &x, why, sizeof(why)));
    CHECK(!cli_parse_double("nan", &x, why, sizeof(why)));
    CHECK(!cli_parse_double("0.5s", &x, why, sizeof(why)));
}

static void timeout_seconds_become_milliseconds(void)
{
    long ms = -1;
    char why[256];

    CHECK(cli_parse_timeout("30", &ms, why, sizeof(why)));
    CHECK_INT(ms, 30000);
    CHECK(cli_parse_timeout("2.5", &ms, why, sizeof(why)));
    CHECK_INT(ms, 2500);
    CHECK(cli_parse_timeout("0", &ms, why, sizeof(why)));
    CHECK_INT(ms, 0);
    /* A tiny positive timeout must not turn into 0, which means "no limit". */
    CHECK(cli_parse_timeout("0.0001", &ms, why, sizeof(why)));
    CHECK_INT(ms, 1);
    CHECK(!cli_parse_timeout("-1", &ms, why, sizeof(why)));
    CHECK(!cli_parse_timeout("abc", &ms, why, sizeof(why)));
    CHECK_CONTAINS(why, "got \"abc\"");
    CHECK(!cli_parse_timeout("1e12", &ms, why, sizeof(why)));
}

static void format_follows_the_output_extension(void)
{
    CHECK_STR(cli_format_from_path("out.png"), "png");
    CHECK_STR(cli_format_from_path("renders/OUT.PNG"), "png");
    CHECK_STR(cli_format_from_path("a.jpg"), "jpeg");
    CHECK_STR(cli_format_from_path("a.JPEG"), "jpeg");
    CHECK_STR(cli_format_from_path("/tmp/x.y/view.exr"), "exr");
    CHECK(cli_format_from_path("out") == NULL);
    CHECK(cli_format_from_path("out.tif") == NULL);
    CHECK(cli_format_from_path(".png") == NULL);
    CHECK(cli_format_from_path("dir.png/out") == NULL);
    CHECK(cli_format_from_path("out.") == NULL);
    CHECK_STR(cli_format_canonical("JPG"), "jpeg");
    CHECK_STR(cli_format_canonical("exr"), "exr");
    CHECK(cli_format_canonical("gif") == NULL);
}

static void format_follows_the_reply_content_type(void)
{
    CHECK_STR(cli_format_from_content_type("image/png"), "png");
    CHECK_STR(cli_format_from_content_type("image/jpeg; q=1"), "jpeg");
    CHECK_STR(cli_format_from_content_type("Image/X-EXR"), "exr");
    CHECK(cli_format_from_content_type("image/pngx") == NULL);
    CHECK(cli_format_from_content_type("text/html") == NULL);
    CHECK(cli_format_from_content_type("") == NULL);
}

static void volume_size_is_x_y_z_c_times_four_without_overflow(void)
{
    uint64_t bytes = 0;

    CHECK(cli_volume_bytes((const int[3]){64, 64, 64}, 1, &bytes));
    CHECK_INT(bytes, 64 * 64 * 64 * 4);
    CHECK(cli_volume_bytes((const int[3]){2, 3, 4}, 5, &bytes));
    CHECK_INT(bytes, 2 * 3 * 4 * 5 * 4);
    /* 65536^4 * 4 = 2^66 does not fit 64 bits. */
    CHECK(!cli_volume_bytes((const int[3]){65536, 65536, 65536}, 65536, &bytes));
    CHECK(!cli_volume_bytes((const int[3]){0, 4, 4}, 1, &bytes));
    CHECK(!cli_volume_bytes((const int[3]){4, 4, 4}, 0, &bytes));
}

enum { T_OUT, T_WIDTH, T_VERBOSE, T_COUNT };

static void option_scan(struct cli_opt *opts, struct cli_parsed *p, char *why, int argc,
                        char **argv, int expect)
{
    opts[T_OUT] = (struct cli_opt){.name = "--output", .alias = "-o", .takes_value = true};
    opts[T_WIDTH] = (struct cli_opt){.name = "--width", .takes_value = true};
    opts[T_VERBOSE] = (struct cli_opt){.name = "--verbose"};
    why[0] = '\0';
    CHECK_INT(cli_parse_args(argc, argv, opts, T_COUNT, p, why, 256), expect);
}

static void options_take_values_in_both_forms_and_keep_positionals(void)
{
    char *argv[] = {"scene-1", "-o", "out.png", "--width=640", "--verbose", "-", "--", "--width"};
    struct cli_opt opts[T_COUNT];
    struct cli_parsed p;
    char why[256];

    option_scan(opts, &p, why, 8, argv, REFRACT_E_OK);
    CHECK_STR(opts[T_OUT].value, "out.png");
    CHECK_STR(opts[T_WIDTH].value, "640");
    CHECK(opts[T_VERBOSE].given);
    CHECK(opts[T_VERBOSE].value == NULL);
    CHECK_INT(p.n_pos, 3);
    CHECK_STR(p.pos[0], "scene-1");
    CHECK_STR(p.pos[1], "-");       /* stdin/stdout, not an option */
    CHECK_STR(p.pos[2], "--width"); /* after "--", everything is positional */
    CHECK(!p.help);
}

static void option_values_may_start_with_a_dash(void)
{
    char *argv[] = {"--width", "-1", "-h"};
    struct cli_opt opts[T_COUNT];
    struct cli_parsed p;
    char why[256];

    option_scan(opts, &p, why, 3, argv, REFRACT_E_OK);
    CHECK_STR(opts[T_WIDTH].value, "-1");
    CHECK(p.help);
}

static void options_reject_typos_repeats_and_missing_values(void)
{
    char *typo[] = {"--widht", "3"};
    char *twice[] = {"--width", "3", "--width=4"};
    char *missing[] = {"x", "--width"};
    char *flag_value[] = {"--verbose=yes"};
    char *far_off[] = {"--zzzzzzzz"};
    struct cli_opt opts[T_COUNT];
    struct cli_parsed p;
    char why[256];

    option_scan(opts, &p, why, 2, typo, REFRACT_E_USAGE);
    CHECK_STR(why, "unknown option '--widht'; did you mean '--width'?");
    option_scan(opts, &p, why, 3, twice, REFRACT_E_USAGE);
    CHECK_STR(why, "--width is given twice");
    option_scan(opts, &p, why, 2, missing, REFRACT_E_USAGE);
    CHECK_STR(why, "--width needs a value");
    option_scan(opts, &p, why, 1, flag_value, REFRACT_E_USAGE);
    CHECK_STR(why, "--verbose takes no value");
    option_scan(opts, &p, why, 1, far_off, REFRACT_E_USAGE);
    CHECK_STR(why, "unknown option '--zzzzzzzz'");
}

static void positionals_beyond_the_limit_are_an_error(void)
{
    char *argv[CLI_MAX_POSITIONALS + 1];
    struct cli_opt opts[T_COUNT];
    struct cli_parsed p;
    char why[256];

    for (size_t i = 0; i < CLI_MAX_POSITIONALS + 1; i++)
        argv[i] = "x";
    argv[CLI_MAX_POSITIONALS] = "extra";
    option_scan(opts, &p, why, CLI_MAX_POSITIONALS + 1, argv, REFRACT_E_USAGE);
    CHECK_STR(why, "unexpected argument 'extra'");
}

static void url_escape_keeps_unreserved_and_encodes_the_rest(void)
{
    char out[64];

    CHECK_INT(refract_url_escape(out, sizeof(out), "scene-7f3a_b.c~"), 15);
    CHECK_STR(out, "scene-7f3a_b.c~");
    refract_url_escape(out, sizeof(out), "a/b c");
    CHECK_STR(out, "a%2Fb%20c");
    refract_url_escape(out, sizeof(out), "?#&=%+");
    CHECK_STR(out, "%3F%23%26%3D%25%2B");
    refract_url_escape(out, sizeof(out), "\xC3\xBC"); /* u with umlaut in UTF-8 */
    CHECK_STR(out, "%C3%BC");
}

static void url_escape_turns_dot_segments_into_plain_names(void)
{
    char out[64];

    refract_url_escape(out, sizeof(out), "..");
    CHECK_STR(out, "%2E%2E");
    refract_url_escape(out, sizeof(out), ".");
    CHECK_STR(out, "%2E");
    refract_url_escape(out, sizeof(out), "..a");
    CHECK_STR(out, "..a");
}

static void url_escape_reports_the_full_length_when_cut(void)
{
    char out[4];
    char *dup = refract_url_escape_dup("a b");

    CHECK_INT(refract_url_escape(out, sizeof(out), "a b"), 5);
    CHECK_STR(out, "a%2");
    CHECK_INT(refract_url_escape(NULL, 0, "a b"), 5);
    CHECK_STR(dup, "a%20b");
    free(dup);
}

static void url_join_puts_exactly_one_slash_between_base_and_path(void)
{
    char *a = refract_url_join("http://127.0.0.1:8750/", "/v1/health");
    char *b = refract_url_join("http://h:1", "v1/scenes");
    char *c = refract_url_join("http://h:1//", "");
    char *d = refract_url_join("http://h:1/prefix", "/v1/health");

    CHECK_STR(a, "http://127.0.0.1:8750/v1/health");
    CHECK_STR(b, "http://h:1/v1/scenes");
    CHECK_STR(c, "http://h:1");
    CHECK_STR(d, "http://h:1/prefix/v1/health");
    free(a);
    free(b);
    free(c);
    free(d);
}

static void url_check_accepts_http_and_https_with_a_host(void)
{
    CHECK(refract_url_is_http("http://127.0.0.1:8750"));
    CHECK(refract_url_is_http("HTTPS://render.example:443/"));
    CHECK(!refract_url_is_http("ftp://host"));
    CHECK(!refract_url_is_http("127.0.0.1:8750"));
    CHECK(!refract_url_is_http("http://"));
    CHECK(!refract_url_is_http("http://:8750"));
    CHECK(!refract_url_is_http("http://a b"));
    CHECK(!refract_url_is_http("http://a\n"));
    CHECK(!refract_url_is_http(""));
}

static void image_size_reads_png_jpeg_and_exr_headers(void)
{
    static const unsigned char png[24] = {0x89, 'P', 'N',  'G',  '\r', '\n', 0x1A, '\n',
                                          0,    0,   0,    13,   'I',  'H',  'D',  'R',
                                          0,    0,   0x02, 0x80, 0,    0,    0x01, 0xE0};
    /* SOI, an APP0 segment of length 4, then SOF0: length 11, precision 8, 480 x 640. */
    static const unsigned char jpeg[] = {0xFF, 0xD8, 0xFF, 0xE0, 0x00, 0x04, 'J',
                                         'F',  0xFF, 0xC0, 0x00, 0x0B, 0x08, 0x01,
                                         0xE0, 0x02, 0x80, 0x01, 0x01, 0x11, 0x00};
    /* Magic, version 2, one "channels"-like attribute to skip, then dataWindow of
     * (-1, 2) .. (638, 481): 640 x 480. */
    static const unsigned char exr[] = {
        0x76, 0x2F, 0x31, 0x01, 2,   0,   0,    0,    'c', 'o', 'm',  'p',  'r', 'e',  's',
        's',  'i',  'o',  'n',  0,   'c', 'o',  'm',  'p', 'r', 'e',  's',  's', 'i',  'o',
        'n',  0,    1,    0,    0,   0,   0,    'd',  'a', 't', 'a',  'W',  'i', 'n',  'd',
        'o',  'w',  0,    'b',  'o', 'x', '2',  'i',  0,   16,  0,    0,    0,   0xFF, 0xFF,
        0xFF, 0xFF, 2,    0,    0,   0,   0x7E, 0x02, 0,   0,   0xE1, 0x01, 0,   0,    0};
    long w = 0;
    long h = 0;

    CHECK(cli_image_size(png, sizeof(png), &w, &h));
    CHECK_INT(w, 640);
    CHECK_INT(h, 480);
    w = h = 0;
    CHECK(cli_image_size(jpeg, sizeof(jpeg), &w, &h));
    CHECK_INT(w, 640);
    CHECK_INT(h, 480);
    w = h = 0;
    CHECK(cli_image_size(exr, sizeof(exr), &w, &h));
    CHECK_INT(w, 640);
    CHECK_INT(h, 480);
}

static void image_size_refuses_cut_or_foreign_bytes(void)
{
    static const unsigned char html[] = "<html><body>502</body></html>";
    static const unsigned char png_cut[12] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    static const unsigned char jpeg_cut[] = {0xFF, 0xD8, 0xFF, 0xC0, 0x00, 0x0B, 0x08};
    static const unsigned char exr_cut[] = {0x76, 0x2F, 0x31, 0x01, 2,   0,   0,  0,
                                            'd',  'a',  't',  'a',  'W', 'i', 'n'};
    long w = 7;
    long h = 7;

    CHECK(!cli_image_size(html, sizeof(html), &w, &h));
    CHECK(!cli_image_size(png_cut, sizeof(png_cut), &w, &h));
    CHECK(!cli_image_size(jpeg_cut, sizeof(jpeg_cut), &w, &h));
    CHECK(!cli_image_size(exr_cut, sizeof(exr_cut), &w, &h));
    CHECK(!cli_image_size(NULL, 0, &w, &h));
    CHECK_INT(w, 7); /* left alone on failure */
    CHECK_INT(h, 7);
}

/* ---- refract light set: flags, type fit, merged light ---------------------------------- */

static bool spec_of(struct cli_light_flags flags, struct cli_light_spec *spec, char *why)
{
    why[0] = '\0';
    return cli_light_spec_parse(&flags, spec, why, 256);
}

static void light_flags_parse_every_value(void)
{
    struct cli_light_spec spec;
    char why[256];

    CHECK(spec_of((struct cli_light_flags){.type = "Spot",
                                           .direction = "0,-1,0",
                                           .position = "0, 2 ,0",
                                           .angle = "25",
                                           .color = "1,0.5,0.25",
                                           .intensity = "3e2"},
                  &spec, why));
    CHECK_STR(spec.type, "spot"); /* canonical, whatever the case given */
    CHECK(spec.has_direction && spec.has_position && spec.has_angle);
    CHECK(spec.has_color && spec.has_intensity);
    CHECK_NEAR(spec.direction[1], -1.0, 0);
    CHECK_NEAR(spec.position[1], 2.0, 0);
    CHECK_NEAR(spec.angle_deg, 25.0, 0);
    CHECK_NEAR(spec.color[2], 0.25, 0);
    CHECK_NEAR(spec.intensity, 300.0, 0);
    CHECK(spec_of((struct cli_light_flags){0}, &spec, why));
    CHECK(spec.type == NULL);
    CHECK(!spec.has_direction && !spec.has_position && !spec.has_angle);
    CHECK(!spec.has_color && !spec.has_intensity);
}

static void light_flags_name_the_option_that_is_wrong(void)
{
    struct cli_light_spec spec;
    char why[256];

    CHECK(!spec_of((struct cli_light_flags){.type = "sun"}, &spec, why));
    CHECK_STR(why, "--type: expected directional, point or spot, got 'sun'");
    CHECK(!spec_of((struct cli_light_flags){.direction = "0,-1"}, &spec, why));
    CHECK_CONTAINS(why, "--direction: expected three numbers");
    CHECK(!spec_of((struct cli_light_flags){.direction = "0,0,0"}, &spec, why));
    CHECK_CONTAINS(why, "--direction: 0,0,0 points nowhere");
    CHECK(!spec_of((struct cli_light_flags){.position = "1,2,nan"}, &spec, why));
    CHECK_CONTAINS(why, "--position: ");
    CHECK(!spec_of((struct cli_light_flags){.angle = "25deg"}, &spec, why));
    CHECK_STR(why, "--angle: expected a finite number, got \"25deg\"");
    CHECK(!spec_of((struct cli_light_flags){.color = "white"}, &spec, why));
    CHECK_CONTAINS(why, "--color: ");
    CHECK(!spec_of((struct cli_light_flags){.intensity = ""}, &spec, why));
    CHECK_CONTAINS(why, "--intensity: ");
}

static void light_flags_must_fit_the_type(void)
{
    struct cli_light_spec pos, dir, angle, all;
    char why[256];

    spec_of((struct cli_light_flags){.position = "0,2,0"}, &pos, why);
    spec_of((struct cli_light_flags){.direction = "0,-1,0"}, &dir, why);
    spec_of((struct cli_light_flags){.angle = "20"}, &angle, why);
    spec_of((struct cli_light_flags){.position = "0,2,0",
                                     .direction = "0,-1,0",
                                     .angle = "20",
                                     .color = "1,1,1",
                                     .intensity = "2"},
            &all, why);
    CHECK(!cli_light_spec_fits(&pos, "directional", why, sizeof(why)));
    CHECK_CONTAINS(why, "--position does not apply to a directional light");
    CHECK(!cli_light_spec_fits(&dir, "point", why, sizeof(why)));
    CHECK_CONTAINS(why, "--direction does not apply to a point light");
    CHECK(!cli_light_spec_fits(&angle, "point", why, sizeof(why)));
    CHECK_CONTAINS(why, "--angle does not apply to a point light");
    CHECK(!cli_light_spec_fits(&angle, "directional", why, sizeof(why)));
    CHECK(cli_light_spec_fits(&dir, "directional", why, sizeof(why)));
    CHECK(cli_light_spec_fits(&pos, "point", why, sizeof(why)));
    CHECK(cli_light_spec_fits(&all, "spot", why, sizeof(why)));
    CHECK(cli_light_spec_fits(&all, NULL, why, sizeof(why))); /* refractd decides */
}

/* Builds `light set NAME` from flags over existing (JSON text or NULL); returns the
 * light as compact JSON (a new string) or NULL with why filled. */
static char *built(const char *existing_json, const char *name, struct cli_light_flags flags,
                   char *why)
{
    struct cli_light_spec spec;
    cJSON *existing = existing_json != NULL ? cJSON_Parse(existing_json) : NULL;
    cJSON *light;
    char *text = NULL;

    CHECK(spec_of(flags, &spec, why));
    light = cli_light_build(existing, name, &spec, why, 256);
    if (light != NULL)
        text = cJSON_PrintUnformatted(light);
    cJSON_Delete(light);
    cJSON_Delete(existing);
    return text;
}

static void light_set_makes_a_new_light_from_the_flags(void)
{
    char why[256];
    char *a = built(
        NULL, "sun",
        (struct cli_light_flags){.type = "directional", .direction = "0,-1,0.5", .intensity = "2"},
        why);
    char *b = built(NULL, "bulb", (struct cli_light_flags){.position = "0,2,0"}, why);

    CHECK_STR(a, "{\"name\":\"sun\",\"type\":\"directional\",\"direction\":[0,-1,0.5],"
                 "\"intensity\":2}");
    CHECK_STR(b, "{\"name\":\"bulb\",\"position\":[0,2,0]}"); /* type: refractd's default */
    cJSON_free(a);
    cJSON_free(b);
}

static void light_set_keeps_what_it_is_not_told(void)
{
    const char *bulb = "{\"name\":\"bulb\",\"type\":\"point\",\"position\":[0,2,0],"
                       "\"color\":[1,0.9,0.8],\"intensity\":5}";
    char why[256];
    char *moved = built(bulb, "bulb", (struct cli_light_flags){.position = "1,2,0"}, why);

    CHECK_STR(moved, "{\"name\":\"bulb\",\"type\":\"point\",\"position\":[1,2,0],"
                     "\"color\":[1,0.9,0.8],\"intensity\":5}");
    cJSON_free(moved);
}

static void light_set_drops_members_a_new_type_does_not_have(void)
{
    const char *spot = "{\"name\":\"s\",\"type\":\"spot\",\"position\":[0,2,0],"
                       "\"direction\":[0,-1,0],\"angle_deg\":25,\"color\":[1,0,0],"
                       "\"future_member\":7}";
    char why[256];
    char *dir = built(spot, "s", (struct cli_light_flags){.type = "directional"}, why);
    char *point = built(spot, "s", (struct cli_light_flags){.type = "point"}, why);
    char *back = built("{\"name\":\"s\",\"type\":\"point\",\"position\":[0,2,0]}", "s",
                       (struct cli_light_flags){.type = "spot", .direction = "0,-1,0"}, why);

    CHECK_STR(dir, "{\"name\":\"s\",\"type\":\"directional\",\"direction\":[0,-1,0],"
                   "\"color\":[1,0,0],\"future_member\":7}");
    CHECK_STR(point, "{\"name\":\"s\",\"type\":\"point\",\"position\":[0,2,0],"
                     "\"color\":[1,0,0],\"future_member\":7}");
    CHECK_STR(back, "{\"name\":\"s\",\"type\":\"spot\",\"position\":[0,2,0],"
                    "\"direction\":[0,-1,0]}");
    cJSON_free(dir);
    cJSON_free(point);
    cJSON_free(back);
}

static void light_set_checks_flags_against_the_existing_type(void)
{
    char why[256];
    char *none = built("{\"name\":\"sun\",\"type\":\"directional\",\"direction\":[0,-1,0]}", "sun",
                       (struct cli_light_flags){.position = "0,3,0"}, why);

    CHECK(none == NULL);
    CHECK_CONTAINS(why, "--position does not apply to a directional light");
}

static void light_find_uses_refractds_default_names(void)
{
    cJSON *doc = cJSON_Parse("{\"lights\":[{\"name\":\"sun\",\"type\":\"directional\"},"
                             "{\"type\":\"point\",\"position\":[0,1,0]}]}");
    const cJSON *second = cli_light_find(doc, "light1");

    CHECK(cli_light_find(doc, "sun") == cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "lights"), 0));
    CHECK(second == cJSON_GetArrayItem(cJSON_GetObjectItem(doc, "lights"), 1));
    CHECK(cli_light_find(doc, "light0") == NULL); /* light 0 has a name of its own */
    CHECK(cli_light_find(doc, "moon") == NULL);
    CHECK(cli_light_find(NULL, "sun") == NULL);
    cJSON_Delete(doc);
}

/* ---- irradiance status: reading and showing it ----------------------------------------- */

static const char status_doc[] =
    "{\"scene\":\"s1\",\"needed\":true,\"transport_hash\":\"0123456789abcdef\",\"lights\":["
    "{\"name\":\"sun\",\"state\":\"ready\",\"progress\":1,\"patches_live\":0,"
    "\"key\":\"fedcba9876543210\",\"gpu_bytes\":2097152,\"host_bytes\":0,\"compute_ms\":850,"
    "\"using\":\"current\",\"stats\":{\"steps\":120}},"
    "{\"name\":\"bulb\",\"state\":\"computing\",\"progress\":0.456,\"patches_live\":12034,"
    "\"using\":\"previous\",\"compute_ms\":1234.5},"
    "{\"name\":\"spot\",\"state\":\"failed\",\"message\":\"patch list full\","
    "\"code\":\"gpu_out_of_memory\",\"using\":\"none\"}]}";

static void status_reads_every_member_and_leaves_absent_ones_minus_one(void)
{
    struct refract_irradiance s;
    char why[256] = "";

    CHECK(refract_status_from_json(status_doc, strlen(status_doc), &s, why, sizeof(why)));
    CHECK_STR(s.scene, "s1");
    CHECK(s.needed);
    CHECK_STR(s.transport_hash, "0123456789abcdef");
    CHECK_INT(s.light_count, 3);
    if (s.light_count == 3) {
        CHECK_STR(s.lights[0].name, "sun");
        CHECK_STR(s.lights[0].state, "ready");
        CHECK_STR(s.lights[0].key, "fedcba9876543210");
        CHECK_INT(s.lights[0].gpu_bytes, 2097152);
        CHECK_INT(s.lights[0].host_bytes, 0);
        CHECK_NEAR(s.lights[0].compute_ms, 850, 0);
        CHECK_STR(s.lights[0].using_volume, "current");
        CHECK_NEAR(s.lights[1].progress, 0.456, 1e-12);
        CHECK_INT(s.lights[1].patches_live, 12034);
        CHECK_INT(s.lights[1].gpu_bytes, -1);
        CHECK_STR(s.lights[1].key, "");
        CHECK_STR(s.lights[2].message, "patch list full");
        CHECK_INT(s.lights[2].code, REFRACT_E_GPU_OUT_OF_MEMORY);
        CHECK_INT(s.lights[1].code, 0);
        CHECK(s.lights[2].progress < 0);
    }
    CHECK(!refract_irradiance_settled(&s)); /* bulb is computing */
    strcpy(s.lights[1].state, "ready");
    CHECK(refract_irradiance_settled(&s)); /* ready and failed are both settled */
    strcpy(s.lights[0].state, "stale");
    CHECK(!refract_irradiance_settled(&s));
    strcpy(s.lights[0].state, "a_state_from_the_future");
    CHECK(!refract_irradiance_settled(&s)); /* unknown: still on its way */
    refract_irradiance_free(&s);
    CHECK(s.lights == NULL && s.light_count == 0);
}

static void status_refuses_documents_without_lights_names_or_states(void)
{
    static const struct {
        const char *doc;
        const char *why;
    } bad[] = {
        {"", "expected a JSON object {\"scene\", \"lights\": [...]}"},
        {"[1,2]", "expected a JSON object {\"scene\", \"lights\": [...]}"},
        {"{\"scene\":\"s\"}", "lights: expected an array"},
        {"{\"lights\":{}}", "lights: expected an array"},
        {"{\"lights\":[7]}", "lights[0]: expected an object"},
        {"{\"lights\":[{\"state\":\"ready\"}]}", "lights[0].name: expected a non-empty string"},
        {"{\"lights\":[{\"name\":\"a\",\"state\":\"ready\"},{\"name\":\"b\"}]}",
         "lights[1].state: expected a non-empty string"},
    };
    struct refract_irradiance s;
    char why[256];

    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
        why[0] = '\0';
        CHECK_MSG(!refract_status_from_json(bad[i].doc, strlen(bad[i].doc), &s, why, sizeof(why)),
                  "accepted %s", bad[i].doc);
        CHECK_STR(why, bad[i].why);
        CHECK(s.lights == NULL && s.light_count == 0);
    }
    CHECK(refract_status_from_json("{\"lights\":[]}", 13, &s, why, sizeof(why)));
    CHECK(s.needed);                       /* absent: assume needed, the cautious reading */
    CHECK(refract_irradiance_settled(&s)); /* no lights: nothing to wait for */
    refract_irradiance_free(&s);
}

static void sizes_and_times_read_like_people_write_them(void)
{
    char b[32];

    cli_format_bytes(b, sizeof(b), -1);
    CHECK_STR(b, "-");
    cli_format_bytes(b, sizeof(b), 0);
    CHECK_STR(b, "0 B");
    cli_format_bytes(b, sizeof(b), 1023);
    CHECK_STR(b, "1023 B");
    cli_format_bytes(b, sizeof(b), 2048);
    CHECK_STR(b, "2.0 KiB");
    cli_format_bytes(b, sizeof(b), 64LL * 64 * 64 * 16); /* a 64^3 RGBA16F + dir volume */
    CHECK_STR(b, "4.0 MiB");
    cli_format_bytes(b, sizeof(b), 3LL << 29);
    CHECK_STR(b, "1.50 GiB");
    cli_format_ms(b, sizeof(b), -1);
    CHECK_STR(b, "-");
    cli_format_ms(b, sizeof(b), 850.4);
    CHECK_STR(b, "850 ms");
    cli_format_ms(b, sizeof(b), 12400);
    CHECK_STR(b, "12.4 s");
    cli_format_ms(b, sizeof(b), 185000);
    CHECK_STR(b, "3 min 05 s");
    /* An absurd ETA is capped (31 years), never undefined or cut short. */
    cli_format_ms(b, sizeof(b), 1e300);
    CHECK_STR(b, "16666666 min 39 s");
    cli_format_bytes(b, sizeof(b), 1024);
    CHECK_STR(b, "1.0 KiB");
    cli_format_bytes(b, sizeof(b), 5LL << 40);
    CHECK_STR(b, "5.00 TiB");
}

static void progress_is_the_mean_over_lights_that_need_a_volume(void)
{
    struct refract_light_status l[4] = {
        {.name = "a", .state = "ready", .progress = 1},
        {.name = "b", .state = "computing", .progress = 0.5},
        {.name = "c", .state = "queued", .progress = 0.9}, /* queued: nothing done yet */
        {.name = "d", .state = "not_needed", .progress = -1},
    };
    struct refract_irradiance s = {.needed = 1, .light_count = 4, .lights = l};
    struct refract_irradiance none = {.needed = 0, .light_count = 1, .lights = &l[3]};
    char bar[64];

    CHECK_NEAR(cli_irradiance_fraction(&s), 0.5, 1e-12);
    CHECK_NEAR(cli_irradiance_fraction(&none), 1.0, 0);
    cli_progress_bar(bar, sizeof(bar), 0.5, 10);
    CHECK_STR(bar, "[#####-----]  50%");
    cli_progress_bar(bar, sizeof(bar), 1.7, 4);
    CHECK_STR(bar, "[####] 100%");
    cli_progress_bar(bar, sizeof(bar), -0.2, 4);
    CHECK_STR(bar, "[----]   0%");
    cli_progress_bar(bar, 6, 0.25, 10); /* no room for the bar: the number alone */
    CHECK_STR(bar, " 25%");
}

static void summary_lines_round_to_steps_for_logs(void)
{
    struct refract_light_status l[2] = {
        {.name = "sun", .state = "ready", .progress = 1, .patches_live = 0},
        {.name = "bulb", .state = "computing", .progress = 0.456, .patches_live = 12034},
    };
    struct refract_irradiance s = {.needed = 1, .light_count = 2, .lights = l};
    struct refract_irradiance empty = {.needed = 1};
    char line[256];

    cli_irradiance_summary(line, sizeof(line), &s, 0);
    CHECK_STR(line, "sun ready, bulb computing 45% (12034 patches)");
    cli_irradiance_summary(line, sizeof(line), &s, 10);
    CHECK_STR(line, "sun ready, bulb computing 40%");
    cli_irradiance_summary(line, 12, &s, 0); /* cut, never overrun */
    CHECK_STR(line, "sun ready, ");
    cli_irradiance_summary(line, sizeof(line), &empty, 0);
    CHECK_STR(line, "no lights");
    /* A photon map is usable from its first pass but not settled until its last. */
    struct refract_light_status map = {.name = "lamp", .state = "ready", .progress = 0.238,
                                       .photon_map = 1, .refining = 1, .photons = 262144};
    struct refract_irradiance refining = {.needed = 1, .light_count = 1, .lights = &map};
    cli_irradiance_summary(line, sizeof(line), &refining, 0);
    CHECK_STR(line, "lamp refining 23%");
    CHECK(!refract_irradiance_settled(&refining));
    CHECK_NEAR(cli_irradiance_fraction(&refining), 0.238, 1e-12);
    map.refining = 0;
    map.progress = 1;
    CHECK(refract_irradiance_settled(&refining));
    cli_irradiance_summary(line, sizeof(line), &refining, 0);
    CHECK_STR(line, "lamp ready");
}

/* Runs f(stream) into memory and returns what it printed (a new string). */
static char *printed(void (*print)(FILE *f, const void *arg), const void *arg)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);

    CHECK(f != NULL);
    if (f == NULL)
        return strdup("");
    print(f, arg);
    fclose(f);
    return text;
}

static void print_table(FILE *f, const void *arg)
{
    cli_irradiance_table(f, arg);
}

static void status_table_has_a_row_per_light_and_the_failures_below(void)
{
    struct refract_irradiance s;
    char why[256];
    char *table;

    CHECK(refract_status_from_json(status_doc, strlen(status_doc), &s, why, sizeof(why)));
    table = printed(print_table, &s);
    CHECK_CONTAINS(table, "scene s1: needs light simulation, transport hash 0123456789abcdef, "
                          "3 lights\n");
    CHECK_CONTAINS(table, "LIGHT  STATE       PROGRESS   PATCHES     GPU MEM    HOST MEM"
                          "     COMPUTE  USING\n");
    CHECK_CONTAINS(table, "sun    ready           100%         0     2.0 MiB         0 B"
                          "      850 ms  current\n");
    CHECK_CONTAINS(table, "bulb   computing        46%     12034           -           -"
                          "       1.2 s  previous\n");
    CHECK_CONTAINS(table, "spot   failed             -         -           -           -"
                          "           -  none\n");
    CHECK_CONTAINS(table, "failed:\n  spot: patch list full\n");
    free(table);
    refract_irradiance_free(&s);
}

/* A photon map's status (docs/photons.md "The cache"): read, not settled while refining,
 * printed as such. */
static void photon_map_status_is_read_and_printed(void)
{
    static const char doc[] =
        "{\"scene\":\"s2\",\"needed\":true,\"lights\":[{\"name\":\"lamp\",\"state\":"
        "\"ready\",\"progress\":0.238,\"patches_live\":0,\"host_bytes\":12582912,"
        "\"using\":\"current\",\"photon_map\":{\"passes\":2,\"passes_total\":3,"
        "\"refining\":true,\"photons\":1048576,\"landed\":158062,\"radius\":0.05}}]}";
    struct refract_irradiance s;
    char why[256] = "";

    CHECK(refract_status_from_json(doc, strlen(doc), &s, why, sizeof(why)));
    CHECK_INT(s.lights[0].photon_map, 1);
    CHECK_INT(s.lights[0].refining, 1);
    CHECK(s.lights[0].photons == 1048576);
    CHECK(!refract_irradiance_settled(&s));
    char *table = printed(print_table, &s);
    CHECK_CONTAINS(table, "scene s2: needs a photon map per light, 1 light\n");
    CHECK_CONTAINS(table, "lamp   refining         24%");
    free(table);
    refract_irradiance_free(&s);
    /* a volume's light has no photon_map */
    CHECK(refract_status_from_json(status_doc, strlen(status_doc), &s, why, sizeof(why)));
    CHECK_INT(s.lights[0].photon_map, 0);
    CHECK(s.lights[0].photons == 0);
    refract_irradiance_free(&s);
}

struct progress_case {
    bool tty;
    int width;
};

static void print_progress(FILE *f, const void *arg)
{
    const struct progress_case *pc = arg;
    struct refract_light_status l = {.name = "sun", .state = "queued", .progress = 0};
    struct refract_irradiance s = {.needed = 1, .light_count = 1, .lights = &l};
    struct cli_progress p;
    static const double steps[] = {0.0, 0.02, 0.05, 0.31, 0.31, 0.33, 1.0};

    cli_progress_init(&p, f, pc->tty, pc->width);
    cli_progress_update(&p, &s);
    strcpy(l.state, "computing");
    for (size_t i = 0; i < sizeof(steps) / sizeof(steps[0]); i++) {
        l.progress = steps[i];
        if (steps[i] == 1.0)
            strcpy(l.state, "ready");
        cli_progress_update(&p, &s);
    }
    cli_progress_finish(&p);
}

static void progress_redraws_a_bar_on_terminals_and_logs_changes_elsewhere(void)
{
    struct progress_case log = {.tty = false, .width = 0};
    struct progress_case tty = {.tty = true, .width = 50};
    char *lines = printed(print_progress, &log);
    char *bar = printed(print_progress, &tty);

    /* One line per state or 10% step; repeats (2%, 5%, 33%) are left out. */
    CHECK_STR(lines, "irradiance: sun queued\n"
                     "irradiance: sun computing 0%\n"
                     "irradiance: sun computing 30%\n"
                     "irradiance: sun ready\n");
    CHECK_CONTAINS(bar, "\r[------------------------]   0%  sun queued\033[K");
    /* cut at 49 columns: a wrapped line could not be redrawn */
    CHECK_CONTAINS(bar, "\r[#######-----------------]  31%  sun computing 31\033[K");
    CHECK_CONTAINS(bar, "\r[########################] 100%  sun ready\033[K\n");
    CHECK(strchr(bar, '\n') == bar + strlen(bar) - 1); /* one line, ended once */
    /* queued, 0%, 2%, 5%, 31%, 33%, 100%: the second 31% is the same line, not redrawn. */
    size_t redraws = 0;
    for (const char *c = bar; (c = strchr(c, '\r')) != NULL; c++)
        redraws++;
    CHECK_INT(redraws, 7);
    free(lines);
    free(bar);
}

/* --orbit: a turn about up keeps the distance to look_at and the height along up; a
 * quarter turn about +y takes +z to +x (right-handed), and 360 degrees comes back. */
static void orbit_turns_the_eye_around_look_at_about_up(void)
{
    const double eye[3] = {1, 2, 5};
    const double at[3] = {1, 0, 1};
    const double up[3] = {0, 3, 0}; /* not unit length on purpose */
    const double zero[3] = {0, 0, 0};
    double out[3];

    CHECK(cli_orbit_eye(eye, at, up, 90, out));
    CHECK_NEAR(out[0], 5, 1e-12);
    CHECK_NEAR(out[1], 2, 1e-12);
    CHECK_NEAR(out[2], 1, 1e-12);
    CHECK(cli_orbit_eye(eye, at, up, 360, out));
    CHECK_NEAR(out[0], 1, 1e-12);
    CHECK_NEAR(out[2], 5, 1e-12);
    CHECK(cli_orbit_eye(eye, at, up, 37, out));
    CHECK_NEAR(sqrt((out[0] - 1) * (out[0] - 1) + (out[2] - 1) * (out[2] - 1)), 4, 1e-12);
    CHECK_NEAR(out[1], 2, 1e-12);
    out[0] = 99;
    CHECK(!cli_orbit_eye(eye, at, zero, 10, out));
    CHECK_NEAR(out[0], 99, 0);
}

static void frame_files_are_numbered_from_one_with_four_digits(void)
{
    char buf[64];

    CHECK(cli_frame_path(buf, sizeof(buf), "out", 1));
    CHECK_STR(buf, "out/frame_0001.jpg");
    CHECK(cli_frame_path(buf, sizeof(buf), "out/", 12345));
    CHECK_STR(buf, "out/frame_12345.jpg");
    CHECK(cli_frame_path(buf, sizeof(buf), "", 7));
    CHECK_STR(buf, "frame_0007.jpg");
    CHECK(!cli_frame_path(buf, 10, "out", 1));
}

/* The options struct sends only what it sets: zero is refractd's default. */
static void view_options_send_only_what_they_set(void)
{
    struct refract_view_options o = {.width = 640,
                                     .height = 480,
                                     .has_eye = 1,
                                     .eye = {0, 1, 4},
                                     .fov_y_deg = 40,
                                     .quality = "draft",
                                     .progressive = -1};
    char *json = refract_view_options_json(&o);

    CHECK_STR(json, "{\"camera\":{\"eye\":[0,1,4],\"fov_y_deg\":40},\"width\":640,\"height\":480,"
                    "\"quality\":\"draft\",\"progressive\":false}");
    free(json);
    json = refract_view_options_json(NULL);
    CHECK_STR(json, "{}");
    free(json);
    memset(&o, 0, sizeof(o));
    o.has_exposure = 1; /* an exposure of 0 is a value when asked for */
    o.max_fps = 2.5;
    o.jpeg_quality = 90;
    o.progressive = 1;
    json = refract_view_options_json(&o);
    CHECK_STR(json, "{\"exposure\":0,\"jpeg_quality\":90,\"max_fps\":2.5,\"progressive\":true}");
    free(json);
}

static void view_status_reads_every_member_and_a_null_frame(void)
{
    static const char full[] =
        "{\"id\": \"v1a2b3c4d5e6f7a8b\", \"scene\": \"wine_glass\", \"camera\": {},"
        " \"width\": 640, \"height\": 480, \"quality\": \"normal\", \"max_fps\": 30,"
        " \"stream\": \"/v1/views/v1a2b3c4d5e6f7a8b/stream\","
        " \"viewer\": \"/viewer/wine_glass?view=v1a2b3c4d5e6f7a8b\", \"streams\": 2,"
        " \"state\": \"idle\", \"expires_in_s\": 118.5, \"renderer\": \"llvmpipe\","
        " \"frame\": {\"seq\": 7, \"kind\": \"preview\", \"width\": 320, \"height\": 240,"
        " \"render_ms\": 35.1, \"encode_ms\": 4.2, \"bytes\": 41234, \"age_ms\": 120.0,"
        " \"irradiance\": \"stale\", \"scene_generation\": 12}, \"new_member\": 1}";
    static const char no_frame[] = "{\"id\": \"v0\", \"frame\": null}";
    struct refract_view v;
    char why[256] = "";

    CHECK(refract_view_from_json(full, sizeof(full) - 1, &v, why, sizeof(why)));
    CHECK_STR(v.id, "v1a2b3c4d5e6f7a8b");
    CHECK_STR(v.scene, "wine_glass");
    CHECK_INT(v.width, 640);
    CHECK_INT(v.height, 480);
    CHECK_STR(v.quality, "normal");
    CHECK_STR(v.state, "idle");
    CHECK_INT(v.streams, 2);
    CHECK_NEAR(v.max_fps, 30, 0);
    CHECK_NEAR(v.expires_in_s, 118.5, 0);
    CHECK_STR(v.renderer, "llvmpipe");
    CHECK_STR(v.stream, "/v1/views/v1a2b3c4d5e6f7a8b/stream");
    CHECK_STR(v.viewer, "/viewer/wine_glass?view=v1a2b3c4d5e6f7a8b");
    CHECK_INT(v.has_frame, 1);
    CHECK_INT(v.frame.seq, 7);
    CHECK_STR(v.frame.kind, "preview");
    CHECK_INT(v.frame.width, 320);
    CHECK_NEAR(v.frame.render_ms, 35.1, 1e-12);
    CHECK_NEAR(v.frame.encode_ms, 4.2, 1e-12);
    CHECK_INT(v.frame.bytes, 41234);
    CHECK_STR(v.frame.irradiance, "stale");
    CHECK_INT(v.frame.scene_generation, 12);
    CHECK(v.json == NULL);

    CHECK(refract_view_from_json(no_frame, sizeof(no_frame) - 1, &v, why, sizeof(why)));
    CHECK_INT(v.has_frame, 0);
    CHECK_INT(v.width, -1);
    CHECK_STR(v.state, "");

    CHECK(!refract_view_from_json("[1]", 3, &v, why, sizeof(why)));
    CHECK_STR(why, "expected a JSON object {\"id\", \"scene\", ...}");
    CHECK(!refract_view_from_json("{\"id\": 5}", 9, &v, why, sizeof(why)));
    CHECK_STR(why, "id: expected a view id string of 1 to 63 characters");
}

static void upload_kind_and_format_follow_the_extension(void)
{
    const char *format = "x";
    CHECK_INT(cli_upload_kind_from_path("scans/ior.nrrd", &format), REFRACT_UPLOAD_VOLUME);
    CHECK_STR(format, "nrrd");
    CHECK_INT(cli_upload_kind_from_path("a.NHDR", &format), REFRACT_UPLOAD_VOLUME);
    CHECK_STR(format, "nrrd");
    CHECK_INT(cli_upload_kind_from_path("d.raw", &format), REFRACT_UPLOAD_VOLUME);
    CHECK_STR(format, "raw");
    CHECK_INT(cli_upload_kind_from_path("gem.ply", &format), REFRACT_UPLOAD_MESH);
    CHECK_STR(format, "ply");
    CHECK_INT(cli_upload_kind_from_path("gem.Obj", &format), REFRACT_UPLOAD_MESH);
    CHECK_STR(format, "obj");
    CHECK_INT(cli_upload_kind_from_path("sky.hdr", &format), REFRACT_UPLOAD_ENVIRONMENT);
    CHECK(format == NULL);
    CHECK_INT(cli_upload_kind_from_path("sky.jpeg", &format), REFRACT_UPLOAD_ENVIRONMENT);
    /* .exr is a volume or an environment: no kind, but its format */
    CHECK_INT(cli_upload_kind_from_path("x.exr", &format), 0);
    CHECK_STR(format, "exr");
    CHECK_INT(cli_upload_kind_from_path("x.nrrd/data", &format), 0);
    CHECK(format == NULL);
    CHECK_INT(cli_upload_kind_from_path(".obj", &format), 0);
    CHECK_INT(cli_upload_kind_from_path("x.tif", &format), 0);
}

static void upload_names_come_from_the_base_name(void)
{
    char name[64];
    CHECK(cli_upload_default_name("scans/ior_64.nrrd", name, sizeof(name)));
    CHECK_STR(name, "ior_64");
    CHECK(cli_upload_default_name("gem-2.ply", name, sizeof(name)));
    CHECK_STR(name, "gem-2");
    CHECK(!cli_upload_default_name("my scan.nrrd", name, sizeof(name))); /* a blank */
    CHECK(!cli_upload_default_name("dir/.raw", name, sizeof(name)));     /* a hidden file */
    CHECK(!cli_upload_default_name("a.b.raw", name, sizeof(name)));      /* "a.b" has a dot */
    char long_name[80];
    memset(long_name, 'a', 64);
    strcpy(long_name + 64, ".raw");
    CHECK(!cli_upload_default_name(long_name, name, sizeof(name)));
}

static void raw_sizes_count_the_bytes_of_each_sample_type(void)
{
    uint64_t bytes = 0;
    CHECK_INT(cli_upload_sample_bytes("float32"), 4);
    CHECK_INT(cli_upload_sample_bytes("float16"), 2);
    CHECK_INT(cli_upload_sample_bytes("uint8"), 1);
    CHECK_INT(cli_upload_sample_bytes("uint16"), 2);
    CHECK_INT(cli_upload_sample_bytes("float64"), 0);
    CHECK_INT(cli_upload_sample_bytes(NULL), 0);
    CHECK(cli_raw_volume_bytes((const int[3]){256, 256, 256}, 3, 1, &bytes));
    CHECK_INT((long long)bytes, 256LL * 256 * 256 * 3);
    CHECK(!cli_raw_volume_bytes((const int[3]){4, 4, 4}, 1, 0, &bytes));
    CHECK(!cli_raw_volume_bytes((const int[3]){1 << 30, 1 << 30, 1 << 30}, 1, 2, &bytes));
}

static void nrrd_headers_with_a_data_file_are_detached(void)
{
    static const char attached[] = "NRRD0004\ntype: float\nsizes: 2 2 2\n\ndata file: x\n";
    static const char detached[] = "NRRD0004\r\ntype: float\r\ndata file: x.raw\r\n\r\n";
    static const char old[] = "NRRD0001\ndatafile: x.raw\n\n";
    CHECK(!cli_upload_nrrd_detached(attached, strlen(attached))); /* after the header: data */
    CHECK(cli_upload_nrrd_detached(detached, strlen(detached)));
    CHECK(cli_upload_nrrd_detached(old, strlen(old)));
    CHECK(!cli_upload_nrrd_detached(detached, 12)); /* cut before the field */
}

static void transfer_lines_give_bytes_percent_speed_and_eta(void)
{
    char t[256];
    cli_transfer_text(t, sizeof(t), 0, 4000000, 0.0, true);
    CHECK_STR(t, "0%  0 B of 3.8 MiB");
    cli_transfer_text(t, sizeof(t), 1000000, 4000000, 0.5, true);
    CHECK_STR(t, "25%  976.6 KiB of 3.8 MiB  2.0 MB/s  ETA 1.5 s");
    cli_transfer_text(t, sizeof(t), 1000000, 4000000, 0.5, false);
    CHECK_STR(t, "976.6 KiB of 3.8 MiB  2.0 MB/s  ETA 1.5 s");
    cli_transfer_text(t, sizeof(t), 4000000, 4000000, 2.0, true);
    CHECK_STR(t, "100%  3.8 MiB of 3.8 MiB  2.0 MB/s  in 2.0 s");
    cli_transfer_text(t, sizeof(t), 3000000, -1, 1.0, true); /* unknown total */
    CHECK_STR(t, "2.9 MiB  3.0 MB/s");
    cli_transfer_text(t, 10, 1000000, 4000000, 0.5, true); /* cut, never overrun */
    CHECK_INT((long long)strlen(t), 9);
}

int main(void)
{
    vec3_parses_three_comma_separated_numbers();
    vec3_rejects_wrong_counts_and_non_finite_values();
    dims_parses_three_positive_integers();
    dims_rejects_zero_negative_fractional_and_oversized();
    numbers_must_be_whole_strings_in_range();
    timeout_seconds_become_milliseconds();
    format_follows_the_output_extension();
    format_follows_the_reply_content_type();
    volume_size_is_x_y_z_c_times_four_without_overflow();
    options_take_values_in_both_forms_and_keep_positionals();
    option_values_may_start_with_a_dash();
    options_reject_typos_repeats_and_missing_values();
    positionals_beyond_the_limit_are_an_error();
    url_escape_keeps_unreserved_and_encodes_the_rest();
    url_escape_turns_dot_segments_into_plain_names();
    url_escape_reports_the_full_length_when_cut();
    url_join_puts_exactly_one_slash_between_base_and_path();
    url_check_accepts_http_and_https_with_a_host();
    image_size_reads_png_jpeg_and_exr_headers();
    image_size_refuses_cut_or_foreign_bytes();
    light_flags_parse_every_value();
    light_flags_name_the_option_that_is_wrong();
    light_flags_must_fit_the_type();
    light_set_makes_a_new_light_from_the_flags();
    light_set_keeps_what_it_is_not_told();
    light_set_drops_members_a_new_type_does_not_have();
    light_set_checks_flags_against_the_existing_type();
    light_find_uses_refractds_default_names();
    status_reads_every_member_and_leaves_absent_ones_minus_one();
    status_refuses_documents_without_lights_names_or_states();
    sizes_and_times_read_like_people_write_them();
    progress_is_the_mean_over_lights_that_need_a_volume();
    summary_lines_round_to_steps_for_logs();
    status_table_has_a_row_per_light_and_the_failures_below();
    photon_map_status_is_read_and_printed();
    progress_redraws_a_bar_on_terminals_and_logs_changes_elsewhere();
    orbit_turns_the_eye_around_look_at_about_up();
    frame_files_are_numbered_from_one_with_four_digits();
    view_options_send_only_what_they_set();
    view_status_reads_every_member_and_a_null_frame();
    upload_kind_and_format_follow_the_extension();
    upload_names_come_from_the_base_name();
    raw_sizes_count_the_bytes_of_each_sample_type();
    nrrd_headers_with_a_data_file_are_detached();
    transfer_lines_give_bytes_percent_speed_and_eta();
    return test_summary("test_cli_args");
}
