/* Every input the fuzzers keep (tests/fuzz/corpus/NAME/, crash reproducers included) goes
 * through its reader in the ordinary and sanitizer builds: the reader must return, and what it
 * accepts must be valid. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "io/bpt.h"
#include "io/step.h"

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0, got;
    char *buf = malloc(cap);
    while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            char *grown = realloc(buf, cap * 2);
            if (!grown)
                free(buf);
            buf = grown;
            cap *= 2;
        }
    }
    fclose(f);
    *len = n;
    return buf;
}

static int run_bpt(const char *data, size_t len, const char *name)
{
    cb_nurbs_surface_struct *p;
    int n;
    cb_error err;
    if (cb_bpt_read_buffer(&p, &n, data, len, name, &err) != CB_OK)
        return 1;
    int ok = 1;
    for (int k = 0; k < n; k++)
        ok &= cb_nurbs_surface_validate(&p[k], &err) == CB_OK;
    cb_nurbs_surface_array_free(p, n);
    return ok;
}

static int run_step(const char *data, size_t len, const char *name)
{
    cb_topo_body *b;
    cb_error err;
    if (cb_step_read_buffer(&b, data, len, name, &err) != CB_OK)
        return 1;
    cb_topo_report r;
    cb_topo_report_init(&r);
    int ok = cb_topo_validate(&r, b, 0, 3, &err) == CB_OK;
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
    return ok;
}

static int run_corpus(const char *root, const char *name, int (*run)(const char *, size_t,
                                                                       const char *))
{
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/tests/fuzz/corpus/%s", root, name);
    DIR *d = opendir(dir);
    CHECK(d != NULL, "corpus %s missing", dir);
    if (!d)
        return 0;
    int count = 0;
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.')
            continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        size_t len = 0;
        char *data = slurp(path, &len);
        CHECK(data != NULL, "%s: unreadable", path);
        if (data)
            CHECK(run(data, len, e->d_name), "%s: accepted but not valid", path);
        free(data);
        count++;
    }
    closedir(d);
    return count;
}

int main(void)
{
    const char *root = getenv("COLIBRI_SOURCE");
    if (!root)
        root = ".";
    int nb = run_corpus(root, "bpt", run_bpt), ns = run_corpus(root, "step", run_step);
    CHECK(nb >= 4 && ns >= 3, "corpora too small: %d .bpt, %d STEP inputs", nb, ns);
    printf("fuzz corpora replayed: %d .bpt, %d STEP inputs\n", nb, ns);
    return check_report("fuzz_regressions");
}
