/*
 * test_cli_args.c - the refract CLI's pure helpers, with no daemon and no network:
 * option scanning, vector/dims/number/timeout parsing, image format from an extension
 * or a Content-Type, volume byte sizes, image sizes read from PNG/JPEG/EXR headers, and
 * librefract's URL joining and path-segment escaping.
 *
 * Unit tests link only the server libraries, so the files under test are compiled
 * into this one directly; none of them uses libcurl or cJSON.
 */
#include <stdint.h>

#include "test.h"

#include "../../client/cli/cli_args.c"
#include "../../client/cli/cli_image.c"
#include "../../client/refract_url.c"

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
    return test_summary("test_cli_args");
}
