/*
 * test.h - the tests' assertion macros. Header-only.
 *
 * Each CHECK prints file:line and what differed when it fails, counts, and lets the
 * test go on so one run shows every failure. A test's main() ends with
 * `return test_summary("name");`, which prints "N passed, N failed" (the line CI
 * reads) and returns non-zero when anything failed. test_setup_failed() fails a test
 * that cannot set up (no GL context, no daemon); test_skip() exits 77 (ctest: skipped)
 * only when a binary is run by hand without the environment ctest sets.
 */
#ifndef REFRACT_TEST_H
#define REFRACT_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int test_passed_count;
static int test_failed_count;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (cond) {                                                                                \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
        }                                                                                          \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                       \
    do {                                                                                           \
        if (cond) {                                                                                \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond);               \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
        }                                                                                          \
    } while (0)

/* |actual - expected| <= tol */
#define CHECK_NEAR(actual, expected, tol)                                                          \
    do {                                                                                           \
        double a_ = (double)(actual), e_ = (double)(expected), t_ = (double)(tol);                 \
        if (fabs(a_ - e_) <= t_) {                                                                 \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr,                                                                        \
                    "%s:%d: CHECK_NEAR failed: %s = %.12g, expected %s = %.12g +- %.3g (off by "   \
                    "%.3g)\n",                                                                     \
                    __FILE__, __LINE__, #actual, a_, #expected, e_, t_, fabs(a_ - e_));            \
        }                                                                                          \
    } while (0)

#define CHECK_INT(actual, expected)                                                                \
    do {                                                                                           \
        long long a_ = (long long)(actual), e_ = (long long)(expected);                            \
        if (a_ == e_) {                                                                            \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr, "%s:%d: CHECK_INT failed: %s = %lld, expected %lld\n", __FILE__,       \
                    __LINE__, #actual, a_, e_);                                                    \
        }                                                                                          \
    } while (0)

#define CHECK_STR(actual, expected)                                                                \
    do {                                                                                           \
        const char *a_ = (actual), *e_ = (expected);                                               \
        if (a_ != NULL && e_ != NULL && strcmp(a_, e_) == 0) {                                     \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr, "%s:%d: CHECK_STR failed: %s = \"%s\", expected \"%s\"\n", __FILE__,   \
                    __LINE__, #actual, a_ ? a_ : "(null)", e_ ? e_ : "(null)");                    \
        }                                                                                          \
    } while (0)

/* strstr(haystack, needle) != NULL */
#define CHECK_CONTAINS(haystack, needle)                                                           \
    do {                                                                                           \
        const char *h_ = (haystack), *n_ = (needle);                                               \
        if (h_ != NULL && strstr(h_, n_) != NULL) {                                                \
            test_passed_count++;                                                                   \
        } else {                                                                                   \
            test_failed_count++;                                                                   \
            fprintf(stderr, "%s:%d: CHECK_CONTAINS failed: %s = \"%s\" lacks \"%s\"\n", __FILE__,  \
                    __LINE__, #haystack, h_ ? h_ : "(null)", n_);                                  \
        }                                                                                          \
    } while (0)

static inline int test_summary(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, test_passed_count, test_failed_count);
    return test_failed_count == 0 && test_passed_count > 0 ? 0 : 1;
}

/* A test that cannot set up what it checks (no GL context, a daemon that does not start)
 * fails: Mesa's software device is a dependency, so in CI this is a real breakage. */
static inline void test_setup_failed(const char *name, const char *why)
{
    printf("%s: FAILED to set up: %s\n", name, why);
    exit(1);
}

/* Only for running a test binary by hand without the environment ctest provides. */
static inline void test_skip(const char *name, const char *why)
{
    printf("%s: SKIPPED: %s\n", name, why);
    exit(77);
}

/* True in the ASan+UBSan build's ctest run (tests/CMakeLists.txt): a test may leave out a
 * repeat of a long numerical case there, since the sanitizers check the code paths, which
 * the first case already runs. */
static inline int test_sanitized(void)
{
    const char *s = getenv("REFRACT_TEST_SANITIZED");
    return s != NULL && s[0] == '1';
}

#endif
