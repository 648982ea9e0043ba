/* Bezier patch text files (io/bpt.c): the shipped teapot and malformed files. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brep/nurbs.h"
#include "check.h"
#include "io/bpt.h"

static const char *shared_dir(void)
{
    const char *d = getenv("COLIBRI_SHARED");
    return d ? d : "../shared";
}

static void test_teapot(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/teapot.bpt", shared_dir());
    cb_nurbs_surface_struct *p = NULL;
    int n = 0;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_bpt_read(&p, &n, path, &err);
    CHECK(st == CB_OK, "%s", err.msg);
    CHECK(n == 32, "teapot has %d patches, 32 expected", n);
    for (int k = 0; k < n; k++) {
        CHECK(p[k].deg_u == 3 && p[k].deg_v == 3 && p[k].n_u == 4 && p[k].n_v == 4,
              "patch %d is not bicubic Bezier", k);
        CHECK(cb_nurbs_surface_validate(&p[k], &err) == CB_OK, "patch %d: %s", k, err.msg);
    }
    if (n == 32) {
        /* First line of patch 0 is "1.4 0.0 2.4"; a Bezier patch interpolates its corners. */
        double c[3];
        cb_nurbs_surface_eval(c, &p[0], 0, 0);
        CHECK(c[0] == 1.4 && c[1] == 0.0 && c[2] == 2.4, "corner (0,0) = %g %g %g", c[0], c[1],
              c[2]);
        /* Rim of the body: patch-0 points at u = 0 lie at height 2.4 and, the cubic being the
         * teapot's approximation of a quarter circle, within 1% of radius 1.4. */
        for (int k = 0; k <= 10; k++) {
            cb_nurbs_surface_eval(c, &p[0], 0, k / 10.0);
            double rad = hypot(c[0], c[1]);
            CHECK(fabs(c[2] - 2.4) < 1e-12 && fabs(rad - 1.4) < 1e-2,
                  "rim point %d: z %g radius %g", k, c[2], rad);
        }
    }
    cb_nurbs_surface_array_free(p, n);
}

/* Writes `text` to a temporary file and expects the reader to fail with `want` and a message
 * holding every word of `words` (the file name, a line number, the problem). */
static void expect_bad(const char *name, const char *text, cb_status want,
                       const char *const *words)
{
    char path[] = "/tmp/colibri_bpt_XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
    cb_nurbs_surface_struct *p = (void *)1;
    int n = -1;
    cb_error err;
    cb_error_clear(&err);
    cb_status st = cb_bpt_read(&p, &n, path, &err);
    CHECK(st == want, "%s: status %d, expected %d (%s)", name, st, want, err.msg);
    CHECK(strstr(err.msg, path) && check_msg_has(err.msg, words), "%s: message '%s'", name,
          err.msg);
    CHECK(p == NULL && n == 0, "%s: outputs not reset on failure", name);
    remove(path);
}

static const char *const ONE_PATCH_HEAD = "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n";

static void test_bad_files(void)
{
    char buf[512];
    expect_bad("empty", "", CB_ERR_PARSE, (const char *const[]){"empty file", NULL});
    expect_bad("count word", "many\n", CB_ERR_PARSE,
               (const char *const[]){":1:", "patch count", "expected 1 numbers", NULL});
    expect_bad("count zero", "0\n", CB_ERR_PARSE,
               (const char *const[]){":1:", "not an integer in [1", NULL});
    expect_bad("fractional degree", "1\n1.5 1\n", CB_ERR_PARSE,
               (const char *const[]){":2:", "patch 0 degrees", NULL});
    expect_bad("huge degree (found by fuzzing)", "1\n1 1888888888888888888888888888888\n",
               CB_ERR_PARSE, (const char *const[]){":2:", "patch 0 degrees", NULL});
    expect_bad("degree 0", "1\n0 3\n", CB_ERR_PARSE,
               (const char *const[]){":2:", "patch 0 degrees", NULL});
    expect_bad("truncated", "1\n1 1\n0 0 0\n0 1 0\n", CB_ERR_PARSE,
               (const char *const[]){"end of file in patch 0 after 2 of 4 points", NULL});
    snprintf(buf, sizeof buf, "%s1 1 0 zz\n", ONE_PATCH_HEAD);
    expect_bad("trailing text", buf, CB_ERR_PARSE,
               (const char *const[]){":6:", "patch 0 point 3", "unexpected text", NULL});
    snprintf(buf, sizeof buf, "%s1 nan 0\n", ONE_PATCH_HEAD);
    expect_bad("NaN", buf, CB_ERR_PARSE,
               (const char *const[]){":6:", "patch 0 point 3", "not a finite", NULL});
    snprintf(buf, sizeof buf, "%s1 1e999 0\n", ONE_PATCH_HEAD);
    expect_bad("overflow", buf, CB_ERR_PARSE, (const char *const[]){":6:", "not a finite", NULL});
    snprintf(buf, sizeof buf, "%s1 1 0\n\n1 1\n", ONE_PATCH_HEAD);
    expect_bad("extra patch", buf, CB_ERR_PARSE,
               (const char *const[]){":8:", "text after the last of 1 patches", NULL});
    expect_bad("count beyond the file", "900000\n1 1\n", CB_ERR_PARSE,
               (const char *const[]){":1:", "900000 patches announced", NULL});
    expect_bad("NUL byte", "1\n1 1\n0 0 0\n0 1 0\n1 0 0\n1 1 \0 0\n", CB_ERR_PARSE,
               (const char *const[]){":6:", "patch 0 point 3", NULL});
    expect_bad("short point", "1\n1 1\n0 0\n", CB_ERR_PARSE,
               (const char *const[]){":3:", "expected 3 numbers, found 2", NULL});

    cb_nurbs_surface_struct *p;
    int n;
    cb_error err;
    CHECK(cb_bpt_read(&p, &n, "/nonexistent/dir/x.bpt", &err) == CB_ERR_IO &&
              strstr(err.msg, "/nonexistent/dir/x.bpt: cannot open"),
          "missing file: '%s'", err.msg);
    CHECK(cb_bpt_read(&p, &n, "/tmp", &err) != CB_OK, "a directory read as a .bpt file");
}

int main(void)
{
    test_teapot();
    test_bad_files();
    return check_report("io_bpt");
}
