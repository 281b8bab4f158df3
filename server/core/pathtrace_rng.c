/*
 * pathtrace_rng.c - PCG32 (pathtrace_rng.h). The stream's increment and start come from
 * splitmix64 of (seed, pixel, sample), so neighbouring pixels and samples get unrelated
 * sequences.
 */
#include "pathtrace_rng.h"

static uint64_t splitmix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

void pathtrace_rng_init(struct pathtrace_rng *r, uint64_t seed, uint64_t pixel, uint64_t sample)
{
    uint64_t h = splitmix64(seed ^ splitmix64(pixel ^ splitmix64(sample)));
    r->state = 0;
    r->inc = (splitmix64(h) << 1) | 1u;
    pathtrace_rng_u32(r);
    r->state += h;
    pathtrace_rng_u32(r);
}

uint32_t pathtrace_rng_u32(struct pathtrace_rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ull + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

double pathtrace_rng_uniform(struct pathtrace_rng *r)
{
    uint64_t hi = pathtrace_rng_u32(r) >> 5; /* 27 bits */
    uint64_t lo = pathtrace_rng_u32(r) >> 6; /* 26 bits */
    return (double)((hi << 26) | lo) * (1.0 / 9007199254740992.0);
}
