/*
 * test_utf8.c - the UTF-8 validator and the \xNN escaping (server/core/utf8.c):
 *   - well_formed_text_is_valid: ASCII, 2-, 3- and 4-byte characters, the edges U+0080,
 *     U+07FF, U+0800, U+FFFF, U+10000, U+10FFFF;
 *   - ill_formed_text_is_found_at_its_first_bad_byte: overlong forms, surrogates, values
 *     above U+10FFFF, stray continuation bytes, truncated sequences, F5..FF, each at the
 *     offset of the sequence that is wrong;
 *   - escape_writes_controls_and_bad_bytes_as_hex: "\n" -> \x0a, DEL, a C1 control, an
 *     invalid byte between valid characters; printable non-ASCII is kept;
 *   - escape_output_is_always_valid_and_one_line: for every byte value alone and for
 *     random byte strings the output is well-formed UTF-8 without control characters;
 *   - escape_truncates_at_whole_units.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/utf8.h"
#include "test.h"

static size_t bad_at(const char *s)
{
    return utf8_invalid_at(s, strlen(s));
}

static void well_formed_text_is_valid(void)
{
    static const char *const ok[] = {"",
                                     "plain ascii",
                                     "caf\xc3\xa9",
                                     "\xc2\x80",
                                     "\xdf\xbf",
                                     "\xe0\xa0\x80",
                                     "\xef\xbf\xbf",
                                     "\xf0\x90\x80\x80",
                                     "\xf4\x8f\xbf\xbf",
                                     "\xe2\x82\xac 10",
                                     "\xf0\x9f\x94\xad telescope"};
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        CHECK_MSG(utf8_valid(ok[i], strlen(ok[i])), "case %zu should be valid", i);
        CHECK_INT((long)bad_at(ok[i]), (long)strlen(ok[i]));
    }
}

static void ill_formed_text_is_found_at_its_first_bad_byte(void)
{
    static const struct {
        const char *text;
        size_t at;
    } bad[] = {
        {"ab\xc0\xaf", 2},           /* overlong '/' */
        {"\xc1\xbf", 0},             /* overlong */
        {"x\xe0\x80\xaf", 1},        /* overlong 3-byte */
        {"\xf0\x80\x80\xaf", 0},     /* overlong 4-byte */
        {"ok\xed\xa0\x80", 2},       /* surrogate U+D800 */
        {"\xed\xbf\xbf", 0},         /* surrogate U+DFFF */
        {"\xf4\x90\x80\x80", 0},     /* U+110000 */
        {"\xf5\x80\x80\x80", 0},     /* F5 never appears */
        {"\xff", 0},                 /* FF never appears */
        {"a\x80", 1},                /* stray continuation */
        {"caf\xc3", 3},              /* truncated at the end */
        {"\xe2\x82 ", 0},            /* truncated by a space */
        {"\xc3\xa9\xe2\x28\xa1", 2}, /* bad second byte after a valid character */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_MSG(!utf8_valid(bad[i].text, strlen(bad[i].text)), "case %zu should be invalid", i);
        CHECK_INT((long)bad_at(bad[i].text), (long)bad[i].at);
    }
}

static void escape_is(const char *in, size_t len, const char *want)
{
    char out[256];
    size_t n = utf8_escape(out, sizeof out, in, len, NULL);
    CHECK_STR(out, want);
    CHECK_INT((long)n, (long)strlen(want));
}

static void escape_writes_controls_and_bad_bytes_as_hex(void)
{
    escape_is("scene\n2026 info forged", 22, "scene\\x0a2026 info forged");
    escape_is("a\r\tb", 4, "a\\x0d\\x09b");
    escape_is("del\x7f", 4, "del\\x7f");
    escape_is("c1\xc2\x85.", 5, "c1\\xc2\\x85.");
    escape_is("caf\xc3\xa9 \xff caf\xc3\xa9", 13, "caf\xc3\xa9 \\xff caf\xc3\xa9");
    escape_is("\xe2\x82", 2, "\\xe2\\x82");
    escape_is("nul\0x", 5, "nul\\x00x");
    escape_is("clean: \xe2\x82\xac", 10, "clean: \xe2\x82\xac");
}

static bool clean_line(const char *s)
{
    size_t len = strlen(s);
    if (!utf8_valid(s, len))
        return false;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 || c == 0x7f)
            return false;
        if (c == 0xc2 && i + 1 < len && (unsigned char)s[i + 1] < 0xa0)
            return false; /* a C1 control */
    }
    return true;
}

static void escape_output_is_always_valid_and_one_line(void)
{
    char out[64];
    int bad = 0;
    for (int b = 0; b < 256; b++) {
        char in[1] = {(char)b};
        utf8_escape(out, sizeof out, in, 1, NULL);
        bad += !clean_line(out);
    }
    CHECK_INT(bad, 0);
    srand(13);
    char in[48], big[48 * 4 + 1];
    for (int round = 0; round < 20000; round++) {
        for (size_t i = 0; i < sizeof in; i++)
            in[i] = (char)(rand() & 0xff);
        utf8_escape(big, sizeof big, in, sizeof in, NULL);
        bad += !clean_line(big);
        /* Escaping is idempotent: clean text comes out as it went in. */
        char again[sizeof big];
        utf8_escape(again, sizeof again, big, strlen(big), NULL);
        bad += strcmp(again, big) != 0;
    }
    CHECK_INT(bad, 0);
}

static void escape_truncates_at_whole_units(void)
{
    char out[6];
    size_t used = 99;
    CHECK_INT((long)utf8_escape(out, sizeof out, "ab\ncd", 5, &used), 2);
    CHECK_STR(out, "ab");
    CHECK_INT((long)used, 2);
    CHECK_INT((long)utf8_escape(out, 4, "a\xc3\xa9", 3, &used), 3);
    CHECK_STR(out, "a\xc3\xa9");
    CHECK_INT((long)used, 3);
    CHECK_INT((long)utf8_escape(out, 3, "a\xc3\xa9", 3, &used), 1);
    CHECK_STR(out, "a");
    CHECK_INT((long)used, 1);
}

int main(void)
{
    well_formed_text_is_valid();
    ill_formed_text_is_found_at_its_first_bad_byte();
    escape_writes_controls_and_bad_bytes_as_hex();
    escape_output_is_always_valid_and_one_line();
    escape_truncates_at_whole_units();
    return test_summary("test_utf8");
}
