/* check.h — the small test harness every test file uses.
 *
 * CHECK(cond, fmt, ...) records a failure with the file, line and a message that shows the
 * failing input; tests keep going so one run reports every broken fact. A test program
 * returns check_report(), which prints "N passed, M failed" and is non-zero on any failure. */
#ifndef CB_TEST_CHECK_H
#define CB_TEST_CHECK_H

#include <stdint.h>
#include <stdio.h>
#include <string.h>

static long check_passed_count, check_failed_count;

#define CHECK(cond, ...)                                                                     \
    do {                                                                                     \
        if (cond) {                                                                          \
            check_passed_count++;                                                            \
        } else {                                                                             \
            check_failed_count++;                                                            \
            if (check_failed_count <= 50) {                                                  \
                fprintf(stderr, "%s:%d: FAILED: %s: ", __FILE__, __LINE__, #cond);           \
                fprintf(stderr, __VA_ARGS__);                                                \
                fputc('\n', stderr);                                                         \
            }                                                                                \
        }                                                                                    \
    } while (0)

static inline int check_report(const char *name)
{
    printf("%s: %ld passed, %ld failed\n", name, check_passed_count, check_failed_count);
    return check_failed_count ? 1 : 0;
}

/* Deterministic generator (splitmix64) so a failure reproduces from its trial number. */
typedef struct {
    uint64_t s;
} check_rng;

static inline uint64_t check_rng_next(check_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static inline double check_rng_uniform(check_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * ((double)(check_rng_next(r) >> 11) * 0x1.0p-53);
}

/* Uniform integer in [lo, hi]. */
static inline int check_rng_int(check_rng *r, int lo, int hi)
{
    return lo + (int)(check_rng_next(r) % (uint64_t)(hi - lo + 1));
}

/* True when msg contains every one of the NULL-terminated substrings. */
static inline int check_msg_has(const char *msg, const char *const *parts)
{
    for (; *parts; parts++)
        if (!strstr(msg, *parts))
            return 0;
    return 1;
}

#endif
