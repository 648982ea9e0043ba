/* The entity table: lookup by #id, typed parameter access with located messages, and the
 * cycle guard used while mapping. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/step_internal.h"

enum { MAX_MAP_DEPTH = 200 };

#define STEP_TYPE_NAME(name) #name,
static const char *const type_names[] = {STEP_TYPES(STEP_TYPE_NAME)};
#undef STEP_TYPE_NAME

const char *step_type_name(step_type t) { return t < STEP_T_COUNT ? type_names[t] : "entity"; }

step_type step_type_lookup(const char *text, int len)
{
    int lo = 0, hi = STEP_T_COUNT - 1;
    while (lo <= hi) {
        int mid = (lo + hi) / 2;
        const char *name = type_names[mid];
        int c = strncmp(text, name, (size_t)len);
        if (!c)
            c = name[len] ? -1 : 0;
        if (!c)
            return (step_type)mid;
        if (c < 0)
            hi = mid - 1;
        else
            lo = mid + 1;
    }
    return STEP_T_OTHER;
}

void step_file_free(step_file *f)
{
    free(f->buf);
    free(f->nodes);
    free(f->parts);
    free(f->recs);
    free(f->state);
    free(f->memo);
    free(f->memo_kind);
    free(f->links);
    memset(f, 0, sizeof *f);
}

const step_rec *step_find(const step_file *f, long id)
{
    int lo = 0, hi = f->n_recs - 1;
    while (lo <= hi) {
        int mid = lo + (hi - lo) / 2;
        long m = f->recs[mid].id;
        if (m == id)
            return &f->recs[mid];
        if (m < id)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return NULL;
}

const step_part *step_part_of(const step_file *f, const step_rec *r, step_type t)
{
    for (int k = 0; k < r->n_parts; k++)
        if (f->parts[r->part0 + k].type == (int)t)
            return &f->parts[r->part0 + k];
    return NULL;
}

step_type step_rec_type(const step_file *f, const step_rec *r)
{
    return (step_type)f->parts[r->part0].type;
}

int step_rec_is(const step_file *f, const step_rec *r, step_type t)
{
    return r->complex ? step_part_of(f, r, t) != NULL : step_rec_type(f, r) == t;
}

/* The name a message gives r: a simple instance's own; for a complex one the leaf type the
 * mapping reads (a B-spline's _WITH_KNOTS part), else its first known part. */
static void rec_name(const step_file *f, const step_rec *r, const char **name, int *len)
{
    const step_part *p = &f->parts[r->part0];
    if (r->complex) {
        const step_part *best = NULL;
        for (int k = 0; k < r->n_parts; k++) {
            const step_part *q = &f->parts[r->part0 + k];
            if (q->type == STEP_T_B_SPLINE_CURVE_WITH_KNOTS ||
                q->type == STEP_T_B_SPLINE_SURFACE_WITH_KNOTS) {
                best = q;
                break;
            }
            if (!best && q->type != STEP_T_OTHER)
                best = q;
        }
        if (best)
            p = best;
    }
    *name = f->buf + p->name_off;
    *len = p->name_len > 64 ? 64 : p->name_len;
}

cb_status step_fail(const step_file *f, const step_rec *r, const step_node *at, cb_status st,
                    const char *fmt, ...)
{
    char msg[CB_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    const char *name;
    int len;
    rec_name(f, r, &name, &len);
    return cb_error_set(f->err, st, "%s:%d: #%ld %.*s: %s", f->path, at ? at->line : r->line, r->id,
                        len, name, msg);
}

cb_status step_fail_prefix(const step_file *f, const step_rec *r, cb_error *err)
{
    const char *name;
    int len;
    rec_name(f, r, &name, &len);
    return cb_error_prefix(err, "%s:%d: #%ld %.*s: ", f->path, r->line, r->id, len, name);
}

const step_node *step_args(const step_file *f, const step_rec *r, const step_part *p, int n)
{
    const step_node *list = &f->nodes[p->args];
    if (list->n != n) {
        step_fail(f, r, list, CB_ERR_PARSE, "%d parameters given, %d expected", list->n, n);
        return NULL;
    }
    return list + 1;
}

const step_node *step_elem(const step_node *list, int i)
{
    const step_node *x = list + 1;
    while (i-- > 0)
        x += x->span;
    return x;
}

static const char *kind_name(const step_node *x)
{
    switch ((step_kind)x->kind) {
    case STEP_INT: return "an integer";
    case STEP_REAL: return "a real";
    case STEP_STRING: return "a string";
    case STEP_ENUM: return "an enumeration";
    case STEP_BINARY: return "a binary";
    case STEP_REF: return "a reference";
    case STEP_UNSET: return "$";
    case STEP_DERIVED: return "*";
    case STEP_LIST: return "a list";
    case STEP_TYPED: return "a typed value";
    }
    return "?";
}

cb_status step_get_real(const step_file *f, const step_rec *r, const step_node *x, const char *what,
                        double *out)
{
    /* A measure may come typed: LENGTH_MEASURE(2.5). */
    if (x->kind == STEP_TYPED && x->n == 1)
        x++;
    if (x->kind != STEP_REAL && x->kind != STEP_INT)
        return step_fail(f, r, x, CB_ERR_PARSE, "%s: a number expected, found %s", what,
                         kind_name(x));
    *out = x->v.real;
    return CB_OK;
}

cb_status step_get_int(const step_file *f, const step_rec *r, const step_node *x, const char *what,
                       long lo, long hi, long *out)
{
    if (x->kind != STEP_INT)
        return step_fail(f, r, x, CB_ERR_PARSE, "%s: an integer expected, found %s", what,
                         kind_name(x));
    if (x->ival < lo || x->ival > hi)
        return step_fail(f, r, x, CB_ERR_INVALID, "%s: %ld is outside [%ld, %ld]", what, x->ival,
                         lo, hi);
    *out = x->ival;
    return CB_OK;
}

int step_is_enum(const step_file *f, const step_node *x, const char *name)
{
    return x->kind == STEP_ENUM && x->v.text.len == (int)strlen(name) &&
           !memcmp(f->buf + x->v.text.off, name, (size_t)x->v.text.len);
}

cb_status step_get_bool(const step_file *f, const step_rec *r, const step_node *x, const char *what,
                        int *out)
{
    if (step_is_enum(f, x, "T") || step_is_enum(f, x, "F")) {
        *out = step_is_enum(f, x, "T");
        return CB_OK;
    }
    return step_fail(f, r, x, CB_ERR_PARSE, "%s: .T. or .F. expected, found %s", what,
                     kind_name(x));
}

cb_status step_get_list(const step_file *f, const step_rec *r, const step_node *x, const char *what,
                        int min_n, int max_n)
{
    if (x->kind != STEP_LIST)
        return step_fail(f, r, x, CB_ERR_PARSE, "%s: a list expected, found %s", what,
                         kind_name(x));
    if (x->n < min_n || x->n > max_n)
        return step_fail(f, r, x, CB_ERR_INVALID, "%s: %d elements, expected %d to %d", what, x->n,
                         min_n, max_n);
    return CB_OK;
}

cb_status step_get_ref(const step_file *f, const step_rec *r, const step_node *x, const char *what,
                       const step_rec **out)
{
    if (x->kind != STEP_REF)
        return step_fail(f, r, x, CB_ERR_PARSE, "%s: a reference expected, found %s", what,
                         kind_name(x));
    if (!(*out = step_find(f, x->v.ref)))
        return step_fail(f, r, x, CB_ERR_INVALID, "%s: #%ld is not defined in the file", what,
                         x->v.ref);
    return CB_OK;
}

cb_status step_enter(step_file *f, const step_rec *r)
{
    int k = step_rec_index(f, r);
    if (f->state[k] == STEP_BUSY)
        return step_fail(f, r, NULL, CB_ERR_INVALID,
                         "cyclic reference: the entity refers back "
                         "to itself");
    if (f->depth >= MAX_MAP_DEPTH)
        return step_fail(f, r, NULL, CB_ERR_INVALID, "references nested deeper than %d",
                         MAX_MAP_DEPTH);
    f->state[k] = STEP_BUSY;
    f->depth++;
    return CB_OK;
}

void step_leave(step_file *f, const step_rec *r)
{
    f->state[step_rec_index(f, r)] = STEP_DONE;
    f->depth--;
}
