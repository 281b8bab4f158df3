/*
 * test_json_read.c - json_read.h: paths, whole-document parsing, and the exact code and
 * message of every validation rule the getters enforce.
 */
#include <float.h>
#include <string.h>

#include "scene/json_read.h"
#include "test.h"

/* Parses a literal test document; the tests only use valid ones here. */
static cJSON *doc(const char *text)
{
    cJSON *root = NULL;
    struct err e;
    err_clear(&e);
    enum refract_code rc = jr_parse(text, strlen(text), &root, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "%s: %s", text, e.msg);
    return root;
}

static void joins_paths_with_dots_and_indices(void)
{
    char buf[64];
    CHECK_STR(jr_path(buf, sizeof buf, "objects[0]", "ior"), "objects[0].ior");
    CHECK_STR(jr_path(buf, sizeof buf, "", "camera"), "camera");
    CHECK_STR(jr_path_index(buf, sizeof buf, "objects", 2), "objects[2]");
    CHECK_STR(jr_path_index(buf, sizeof buf, "objects[2].ior", 1), "objects[2].ior[1]");
}

static void parse_rejects_an_empty_body(void)
{
    struct err e;
    cJSON *root = (cJSON *)1;
    CHECK_INT(jr_parse("", 0, &root, &e), REFRACT_E_INVALID_JSON);
    CHECK(root == NULL);
    CHECK_CONTAINS(e.msg, "empty");
    CHECK_INT(jr_parse(" \n\t ", 4, &root, &e), REFRACT_E_INVALID_JSON);
    CHECK_CONTAINS(e.msg, "empty");
    CHECK_INT(jr_parse(NULL, 0, &root, &e), REFRACT_E_INVALID_JSON);
}

static void parse_reports_byte_line_and_column_of_a_syntax_error(void)
{
    /* The error is the '}' at byte 19, line 3, column 8. */
    const char *text = "{\n  \"a\": 1,\n  \"b\": }";
    struct err e;
    cJSON *root;
    CHECK_INT(jr_parse(text, strlen(text), &root, &e), REFRACT_E_INVALID_JSON);
    CHECK_CONTAINS(e.msg, "byte 19");
    CHECK_CONTAINS(e.msg, "line 3");
    CHECK_CONTAINS(e.msg, "column 8");
}

static void parse_rejects_trailing_text(void)
{
    const char *text = "{\"a\": 1} x";
    struct err e;
    cJSON *root;
    CHECK_INT(jr_parse(text, strlen(text), &root, &e), REFRACT_E_INVALID_JSON);
    CHECK_CONTAINS(e.msg, "after the JSON document");
    CHECK_CONTAINS(e.msg, "byte 9");
    /* Two documents back to back are trailing text too. */
    CHECK_INT(jr_parse("{}{}", 4, &root, &e), REFRACT_E_INVALID_JSON);
    /* Trailing whitespace is fine. */
    CHECK_INT(jr_parse("{} \r\n", 5, &root, &e), REFRACT_E_OK);
    cJSON_Delete(root);
}

static void parse_reads_only_len_bytes_of_an_unterminated_buffer(void)
{
    /* The body is the first 8 bytes; what follows is not part of it. */
    const char text[] = {'{', '"', 'a', '"', ':', ' ', '1', '}', 'G', 'A', 'R', 'B'};
    struct err e;
    cJSON *root;
    CHECK_INT(jr_parse(text, 8, &root, &e), REFRACT_E_OK);
    CHECK(cJSON_IsObject(root));
    cJSON_Delete(root);
    /* Cut inside the document: a truncation error, not a read past the end. */
    CHECK_INT(jr_parse(text, 6, &root, &e), REFRACT_E_INVALID_JSON);
    CHECK_CONTAINS(e.msg, "truncated");
}

static void parse_rejects_nesting_deeper_than_cjson_allows(void)
{
    size_t depth = 1500;
    char *text = malloc(2 * depth);
    memset(text, '[', depth);
    memset(text + depth, ']', depth);
    struct err e;
    cJSON *root;
    CHECK_INT(jr_parse(text, 2 * depth, &root, &e), REFRACT_E_INVALID_JSON);
    CHECK_CONTAINS(e.msg, "nesting deeper than 1000");
    free(text);
}

static void check_object_rejects_unknown_field_with_path_and_allowed_keys(void)
{
    static const char *const allowed[] = {"shape", "center", "radius", "inside", "outside", NULL};
    cJSON *o = doc("{\"shape\": \"sphere\", \"radious\": 1}");
    struct err e;
    CHECK_INT(jr_check_object(o, "objects[0].ior", allowed, &e), REFRACT_E_UNKNOWN_FIELD);
    CHECK_STR(e.msg, "objects[0].ior: unknown field \"radious\"; allowed: shape, center, radius, "
                     "inside, outside");
    cJSON_Delete(o);
}

static void check_object_matches_keys_case_sensitively(void)
{
    static const char *const allowed[] = {"radius", NULL};
    cJSON *o = doc("{\"Radius\": 1}");
    struct err e;
    CHECK_INT(jr_check_object(o, "x", allowed, &e), REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(e.msg, "\"Radius\"");
    double r;
    CHECK_INT(jr_number(o, "x", "radius", true, 0, 0, 1, &r, &e), REFRACT_E_MISSING_FIELD);
    cJSON_Delete(o);
}

static void check_object_rejects_duplicate_keys(void)
{
    static const char *const allowed[] = {"a", "b", NULL};
    cJSON *o = doc("{\"a\": 1, \"b\": 2, \"a\": 3}");
    struct err e;
    CHECK_INT(jr_check_object(o, "camera", allowed, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "camera.a: duplicate field");
    cJSON_Delete(o);
}

static void check_object_rejects_a_non_object_naming_what_it_got(void)
{
    static const char *const allowed[] = {NULL};
    cJSON *o = doc("[1, 2]");
    struct err e;
    CHECK_INT(jr_check_object(o, "", allowed, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "(root): expected an object, got an array of 2 values");
    cJSON_Delete(o);
}

static void unknown_key_is_quoted_with_escapes_and_shortened(void)
{
    static const char *const allowed[] = {"a", NULL};
    cJSON *o = doc(
        "{\"x\\n\\\"y\\u0001aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\": 1}");
    struct err e;
    CHECK_INT(jr_check_object(o, "p", allowed, &e), REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(e.msg, "\"x\\x0a\\\"y\\x01aaa");
    CHECK_CONTAINS(e.msg, "...\"");
    cJSON_Delete(o);
}

static void unknown_key_keeps_printable_utf8_and_escapes_c1_controls(void)
{
    static const char *const allowed[] = {"a", NULL};
    cJSON *o = doc("{\"gr\u00f6\u00dfe\\u0085\": 1}");
    struct err e;
    CHECK_INT(jr_check_object(o, "p", allowed, &e), REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(e.msg, "\"gr\xc3\xb6\xc3\x9f"
                          "e\\xc2\\x85\"");
    cJSON_Delete(o);
}

static void number_applies_default_and_requires_when_asked(void)
{
    cJSON *o = doc("{}");
    struct err e;
    double v = 0;
    CHECK_INT(jr_number(o, "render", "step", false, 0.5, 0.01, 8, &v, &e), REFRACT_E_OK);
    CHECK_NEAR(v, 0.5, 0);
    CHECK_INT(jr_number(o, "render", "step", true, 0.5, 0.01, 8, &v, &e), REFRACT_E_MISSING_FIELD);
    CHECK_STR(e.msg, "render: missing required field \"step\"");
    CHECK_INT(jr_number(o, "", "objects", true, 0, 0, 1, &v, &e), REFRACT_E_MISSING_FIELD);
    CHECK_STR(e.msg, "(root): missing required field \"objects\"");
    cJSON_Delete(o);
}

static void number_rejects_out_of_range_with_rule_and_value(void)
{
    cJSON *o = doc("{\"step\": 12, \"tiny\": 0.0099999, \"s\": \"abc\", \"n\": null}");
    struct err e;
    double v;
    CHECK_INT(jr_number(o, "render", "step", false, 0.5, 0.01, 8, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "render.step: expected a finite number in 0.01..8, got 12");
    CHECK_INT(jr_number(o, "render", "tiny", false, 0.5, 0.01, 8, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got 0.0099999");
    CHECK_INT(jr_number(o, "render", "s", false, 0.5, 0.01, 8, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got \"abc\"");
    /* null is present, so it is a wrong type, not a default. */
    CHECK_INT(jr_number(o, "render", "n", false, 0.5, 0.01, 8, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got null");
    cJSON_Delete(o);
}

static void number_rejects_overflow_to_infinity(void)
{
    cJSON *o = doc("{\"x\": 1e999, \"y\": -1e999}");
    struct err e;
    double v;
    CHECK_INT(jr_number(o, "a", "x", true, 0, -DBL_MAX, DBL_MAX, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "a.x: expected a finite number, got inf");
    CHECK_INT(jr_number(o, "a", "y", true, 0, -1e6, 1e6, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "-inf");
    cJSON_Delete(o);
}

static void number_gt_excludes_its_minimum(void)
{
    cJSON *o = doc("{\"r\": 0, \"q\": 1e-300}");
    struct err e;
    double v;
    CHECK_INT(jr_number_gt(o, "s", "r", true, 0, 0, 1e6, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "s.r: expected a finite number > 0 and <= 1000000, got 0");
    CHECK_INT(jr_number_gt(o, "s", "q", true, 0, 0, 1e6, &v, &e), REFRACT_E_OK);
    CHECK(v > 0);
    cJSON_Delete(o);
}

static void int_rejects_fractions_and_out_of_range(void)
{
    cJSON *o = doc("{\"a\": 2.5, \"b\": 1e10, \"c\": 7, \"d\": true}");
    struct err e;
    int v;
    CHECK_INT(jr_int(o, "r", "a", true, 0, 1, 100, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "r.a: expected an integer in 1..100, got 2.5");
    CHECK_INT(jr_int(o, "r", "b", true, 0, 1, 100, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_INT(jr_int(o, "r", "d", true, 0, 1, 100, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got true");
    CHECK_INT(jr_int(o, "r", "c", true, 0, 1, 100, &v, &e), REFRACT_E_OK);
    CHECK_INT(v, 7);
    cJSON_Delete(o);
}

static void bool_accepts_only_true_and_false(void)
{
    cJSON *o = doc("{\"a\": true, \"b\": 1}");
    struct err e;
    bool v = false;
    CHECK_INT(jr_bool(o, "x", "a", true, false, &v, &e), REFRACT_E_OK);
    CHECK(v);
    CHECK_INT(jr_bool(o, "x", "b", true, false, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "x.b: expected true or false, got 1");
    CHECK_INT(jr_bool(o, "x", "c", false, true, &v, &e), REFRACT_E_OK);
    CHECK(v);
    cJSON_Delete(o);
}

static void string_checks_type_and_length(void)
{
    cJSON *o = doc("{\"a\": \"hello\", \"b\": \"\", \"c\": \"toolong\", \"d\": 3}");
    struct err e;
    char buf[8];
    CHECK_INT(jr_string(o, "", "a", true, NULL, 5, buf, sizeof buf, &e), REFRACT_E_OK);
    CHECK_STR(buf, "hello");
    CHECK_INT(jr_string(o, "", "b", true, NULL, 5, buf, sizeof buf, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "b: expected a string of 1..5 bytes, got 0 bytes");
    CHECK_INT(jr_string(o, "", "c", true, NULL, 5, buf, sizeof buf, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got 7 bytes");
    CHECK_INT(jr_string(o, "", "d", true, NULL, 5, buf, sizeof buf, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "got 3");
    CHECK_INT(jr_string(o, "", "z", false, "dflt", 5, buf, sizeof buf, &e), REFRACT_E_OK);
    CHECK_STR(buf, "dflt");
    cJSON_Delete(o);
}

static void enum_lists_the_names_it_accepts(void)
{
    static const char *const names[] = {"euler", "rk4", NULL};
    cJSON *o = doc("{\"stepper\": \"rk5\", \"ok\": \"euler\"}");
    struct err e;
    int v = -1;
    CHECK_INT(jr_enum(o, "render", "stepper", false, 1, names, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "render.stepper: expected one of \"euler\", \"rk4\", got \"rk5\"");
    CHECK_INT(jr_enum(o, "render", "ok", false, 1, names, &v, &e), REFRACT_E_OK);
    CHECK_INT(v, 0);
    CHECK_INT(jr_enum(o, "render", "absent", false, 1, names, &v, &e), REFRACT_E_OK);
    CHECK_INT(v, 1);
    cJSON_Delete(o);
}

static void vec3_names_the_bad_element(void)
{
    cJSON *o = doc("{\"a\": [1, 2], \"b\": [1, \"x\", 3], \"c\": [1, 2, 3], \"d\": [0, 9, 0]}");
    struct err e;
    vec3 v = {0, 0, 0};
    CHECK_INT(jr_vec3(o, "camera", "a", true, v, -10, 10, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "camera.a: expected an array of 3 numbers in -10..10, got an array of 2 "
                     "values");
    CHECK_INT(jr_vec3(o, "camera", "b", true, v, -10, 10, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "camera.b[1]: expected a finite number in -10..10, got \"x\"");
    CHECK_INT(jr_vec3(o, "camera", "d", true, v, -5, 5, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "camera.d[1]");
    CHECK_INT(jr_vec3(o, "camera", "c", true, v, -10, 10, &v, &e), REFRACT_E_OK);
    CHECK_NEAR(v.z, 3, 0);
    cJSON_Delete(o);
}

static void direction_is_normalised_and_rejects_zero(void)
{
    cJSON *o = doc("{\"a\": [0, 0, 0], \"b\": [0, 3, 4], \"c\": [1e300, 1e300, 0]}");
    struct err e;
    vec3 v = {0, 0, 0};
    CHECK_INT(jr_direction(o, "camera", "a", true, v, &v, &e), REFRACT_E_INVALID_FIELD);
    CHECK_STR(e.msg, "camera.a: expected a non-zero direction (length > 1e-12), got [0, 0, 0]");
    CHECK_INT(jr_direction(o, "camera", "b", true, v, &v, &e), REFRACT_E_OK);
    CHECK_NEAR(v.y, 0.6, 1e-15);
    CHECK_NEAR(v.z, 0.8, 1e-15);
    CHECK_INT(jr_direction(o, "camera", "c", true, v, &v, &e), REFRACT_E_OK);
    CHECK_NEAR(v.x, sqrt(0.5), 1e-15);
    cJSON_Delete(o);
}

static void describe_names_each_json_type(void)
{
    cJSON *o = doc("{\"a\": {}, \"b\": [1], \"c\": false, \"d\": 1.25}");
    char buf[64];
    CHECK_STR(jr_describe(cJSON_GetObjectItem(o, "a"), buf, sizeof buf), "an object");
    CHECK_STR(jr_describe(cJSON_GetObjectItem(o, "b"), buf, sizeof buf), "an array of 1 value");
    CHECK_STR(jr_describe(cJSON_GetObjectItem(o, "c"), buf, sizeof buf), "false");
    CHECK_STR(jr_describe(cJSON_GetObjectItem(o, "d"), buf, sizeof buf), "1.25");
    CHECK_STR(jr_describe(NULL, buf, sizeof buf), "nothing");
    cJSON_Delete(o);
}

int main(void)
{
    joins_paths_with_dots_and_indices();
    parse_rejects_an_empty_body();
    parse_reports_byte_line_and_column_of_a_syntax_error();
    parse_rejects_trailing_text();
    parse_reads_only_len_bytes_of_an_unterminated_buffer();
    parse_rejects_nesting_deeper_than_cjson_allows();
    check_object_rejects_unknown_field_with_path_and_allowed_keys();
    check_object_matches_keys_case_sensitively();
    check_object_rejects_duplicate_keys();
    check_object_rejects_a_non_object_naming_what_it_got();
    unknown_key_is_quoted_with_escapes_and_shortened();
    unknown_key_keeps_printable_utf8_and_escapes_c1_controls();
    number_applies_default_and_requires_when_asked();
    number_rejects_out_of_range_with_rule_and_value();
    number_rejects_overflow_to_infinity();
    number_gt_excludes_its_minimum();
    int_rejects_fractions_and_out_of_range();
    bool_accepts_only_true_and_false();
    string_checks_type_and_length();
    enum_lists_the_names_it_accepts();
    vec3_names_the_bad_element();
    direction_is_normalised_and_rejects_zero();
    describe_names_each_json_type();
    return test_summary("test_json_read");
}
