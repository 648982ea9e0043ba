/* Reader for Bezier patch text files (.bpt). */
#include "io/bpt.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_PATCHES = 1000000, MAX_LINE = 4096 };

/* The smallest text a patch can take ("1 1\n" and four "0 0 0\n"); a count that the buffer
 * cannot hold is rejected before anything is allocated for it. */
enum { MIN_PATCH_BYTES = 28 };

/* Files larger than this are refused rather than read into memory. */
#define MAX_FILE_BYTES ((size_t)1 << 28)

typedef struct {
    const char *data;
    size_t len, pos;
    const char *path;
    int line;
    int too_long;  /* the current line did not fit in buf */
    char what[64]; /* what the current line should hold, for messages */
    char buf[MAX_LINE];
} line_reader;

/* Next non-blank line into r->buf; 0 at the end of the data. */
static int next_line(line_reader *r)
{
    while (r->pos < r->len) {
        const char *start = r->data + r->pos;
        const char *nl = memchr(start, '\n', r->len - r->pos);
        size_t n = nl ? (size_t)(nl - start) : r->len - r->pos;
        r->pos += n + (nl != NULL);
        r->line++;
        r->too_long = n >= sizeof r->buf;
        if (r->too_long)
            n = sizeof r->buf - 1;
        memcpy(r->buf, start, n);
        r->buf[n] = '\0';
        /* An embedded NUL would hide the rest of the line from the parser: make it visible. */
        for (size_t k = 0; k < n; k++)
            if (r->buf[k] == '\0')
                r->buf[k] = '\x01';
        if (r->too_long || strspn(r->buf, " \t\r") != n)
            return 1;
    }
    return 0;
}

/* Parses exactly `count` numbers from the current line. */
static cb_status parse_numbers(line_reader *r, double *out, int count, cb_error *err)
{
    const char *s = r->buf;
    if (r->too_long)
        return cb_error_set(err, CB_ERR_PARSE, "%s:%d: %s: line longer than %d characters",
                            r->path, r->line, r->what, MAX_LINE - 1);
    for (int k = 0; k < count; k++) {
        char *end;
        errno = 0;
        out[k] = strtod(s, &end);
        if (end == s)
            return cb_error_set(err, CB_ERR_PARSE, "%s:%d: %s: expected %d numbers, found %d",
                                r->path, r->line, r->what, count, k);
        if (errno == ERANGE || out[k] != out[k] || out[k] - out[k] != 0)
            return cb_error_set(err, CB_ERR_PARSE, "%s:%d: %s: number %d is not a finite double",
                                r->path, r->line, r->what, k + 1);
        s = end;
    }
    if (strspn(s, " \t\r\n") != strlen(s))
        return cb_error_set(err, CB_ERR_PARSE, "%s:%d: %s: unexpected text after %d numbers",
                            r->path, r->line, r->what, count);
    return CB_OK;
}

static cb_status parse_int(line_reader *r, int *out, int count, int lo, int hi, cb_error *err)
{
    double v[2] = {0, 0};
    cb_status st = parse_numbers(r, v, count, err);
    if (st)
        return st;
    for (int k = 0; k < count; k++) {
        /* Range first: converting an out-of-range double to an integer is undefined. */
        if (!(v[k] >= lo && v[k] <= hi) || v[k] != (double)(int)v[k])
            return cb_error_set(err, CB_ERR_PARSE, "%s:%d: %s: %g is not an integer in [%d, %d]",
                                r->path, r->line, r->what, v[k], lo, hi);
        out[k] = (int)v[k];
    }
    return CB_OK;
}

static cb_status read_patch(cb_nurbs_surface_t s, line_reader *r, int index, cb_error *err)
{
    int deg[2] = {0, 0};
    if (!next_line(r))
        return cb_error_set(err, CB_ERR_PARSE, "%s:%d: end of file before patch %d", r->path,
                            r->line, index);
    snprintf(r->what, sizeof r->what, "patch %d degrees", index);
    cb_status st = parse_int(r, deg, 2, 1, CB_MAX_DEGREE, err);
    if (st)
        return st;
    int m = deg[0], n = deg[1], count = (m + 1) * (n + 1);
    if ((st = cb_nurbs_surface_alloc(s, m, n, m + 1, n + 1, err)))
        return st;
    for (int k = 0; k <= m; k++) {
        s->knots_u[k] = 0.0;
        s->knots_u[m + 1 + k] = 1.0;
    }
    for (int k = 0; k <= n; k++) {
        s->knots_v[k] = 0.0;
        s->knots_v[n + 1 + k] = 1.0;
    }
    for (int k = 0; k < count; k++) {
        if (!next_line(r))
            return cb_error_set(err, CB_ERR_PARSE,
                                "%s:%d: end of file in patch %d after %d of %d points", r->path,
                                r->line, index, k, count);
        double *pw = s->cw + 4 * k;
        snprintf(r->what, sizeof r->what, "patch %d point %d", index, k);
        if ((st = parse_numbers(r, pw, 3, err)))
            return st;
        pw[3] = 1.0;
    }
    return CB_OK;
}

cb_status cb_bpt_read_buffer(cb_nurbs_surface_struct **patches, int *n_patches,
                             const char *data, size_t len, const char *name, cb_error *err)
{
    *patches = NULL;
    *n_patches = 0;
    line_reader r = {.data = data, .len = len, .path = name};
    cb_status st = CB_OK;
    int count = 0;
    cb_nurbs_surface_struct *arr = NULL;
    if (!next_line(&r)) {
        st = cb_error_set(err, CB_ERR_PARSE, "%s: empty file, expected a patch count", name);
    } else {
        snprintf(r.what, sizeof r.what, "patch count");
        st = parse_int(&r, &count, 1, 1, MAX_PATCHES, err);
    }
    if (!st && (size_t)count > len / MIN_PATCH_BYTES + 1)
        st = cb_error_set(err, CB_ERR_PARSE, "%s:%d: %d patches announced, but %zu bytes hold at "
                          "most %zu", name, r.line, count, len, len / MIN_PATCH_BYTES + 1);
    if (!st && !(arr = calloc((size_t)count, sizeof *arr)))
        st = cb_error_set(err, CB_ERR_NOMEM, "%s: no memory for %d patches", name, count);
    for (int k = 0; !st && k < count; k++)
        st = read_patch(&arr[k], &r, k, err);
    if (!st && next_line(&r))
        st = cb_error_set(err, CB_ERR_PARSE, "%s:%d: text after the last of %d patches", name,
                          r.line, count);
    if (st) {
        cb_nurbs_surface_array_free(arr, arr ? count : 0);
        return st;
    }
    *patches = arr;
    *n_patches = count;
    return CB_OK;
}

cb_status cb_bpt_read(cb_nurbs_surface_struct **patches, int *n_patches, const char *path,
                      cb_error *err)
{
    *patches = NULL;
    *n_patches = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return cb_error_set(err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    cb_status st = CB_OK;
    char *data = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len == cap) {
            if (cap >= MAX_FILE_BYTES) {
                st = cb_error_set(err, CB_ERR_PARSE, "%s: larger than %zu bytes", path,
                                  MAX_FILE_BYTES);
                break;
            }
            cap = cap ? 2 * cap : 1 << 16;
            char *grown = realloc(data, cap);
            if (!grown) {
                st = cb_error_set(err, CB_ERR_NOMEM, "%s: no memory to read the file", path);
                break;
            }
            data = grown;
        }
        size_t got = fread(data + len, 1, cap - len, f);
        len += got;
        if (got == 0)
            break;
    }
    if (!st && ferror(f))
        st = cb_error_set(err, CB_ERR_IO, "%s: read error: %s", path, strerror(errno));
    fclose(f);
    if (!st)
        st = cb_bpt_read_buffer(patches, n_patches, data, len, path, err);
    free(data);
    return st;
}
