/*
 * sha256.h - SHA-256 (FIPS 180-4), incremental: the content address of the data
 * directory's blobs (server/store/) and of uploads hashed as their bytes arrive
 * (server/http/server.c). Not a MAC and not constant-time: it names content, it guards
 * nothing secret.
 *
 *     struct sha256 h;
 *     sha256_init(&h);
 *     sha256_update(&h, bytes, len);      // any number of times
 *     char hex[SHA256_HEX_SIZE];
 *     sha256_final_hex(&h, hex);          // 64 lowercase hex digits + NUL
 */
#ifndef REFRACT_SHA256_H
#define REFRACT_SHA256_H

#include <stddef.h>
#include <stdint.h>

#define SHA256_HEX_SIZE 65

struct sha256 {
    uint32_t state[8];
    uint64_t length_bytes;
    unsigned char block[64];
    size_t block_used;
};

void sha256_init(struct sha256 *h);
void sha256_update(struct sha256 *h, const void *data, size_t len);
/* Finishes the hash (h must be re-initialised before reuse). */
void sha256_final(struct sha256 *h, unsigned char digest[32]);
void sha256_final_hex(struct sha256 *h, char hex[SHA256_HEX_SIZE]);

#endif
