/*
 * test_sha256.c - sha256 (server/core/sha256.c) gives the FIPS 180-4 example digests
 * ("abc", the empty string, the 448-bit two-block message) and a million 'a's, and the
 * same digest whatever the split of the input into updates (the streamed uploads hash
 * chunks of any size).
 */
#include <string.h>

#include "core/sha256.h"
#include "test.h"

static void hex_of(const void *data, size_t len, char out[SHA256_HEX_SIZE])
{
    struct sha256 h;
    sha256_init(&h);
    sha256_update(&h, data, len);
    sha256_final_hex(&h, out);
}

static void fips_examples_match(void)
{
    char hex[SHA256_HEX_SIZE];
    hex_of("abc", 3, hex);
    CHECK_STR(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    hex_of("", 0, hex);
    CHECK_STR(hex, "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const char *two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    hex_of(two, strlen(two), hex);
    CHECK_STR(hex, "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

static void million_a_in_any_split(void)
{
    static char a[1000000];
    memset(a, 'a', sizeof a);
    const char *want = "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0";
    char hex[SHA256_HEX_SIZE];
    hex_of(a, sizeof a, hex);
    CHECK_STR(hex, want);
    static const size_t steps[] = {1, 55, 63, 64, 65, 4097};
    for (size_t k = 0; k < sizeof steps / sizeof steps[0]; k++) {
        struct sha256 h;
        sha256_init(&h);
        for (size_t off = 0; off < sizeof a; off += steps[k]) {
            size_t n = sizeof a - off < steps[k] ? sizeof a - off : steps[k];
            sha256_update(&h, a + off, n);
        }
        sha256_final_hex(&h, hex);
        CHECK_STR(hex, want);
    }
}

int main(void)
{
    fips_examples_match();
    million_a_in_any_split();
    return test_summary("test_sha256");
}
