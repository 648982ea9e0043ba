/* Entry points of the STEP reader: load the file, parse, map, index, complete the pcurves,
 * fit the edge tolerances. */
#define _POSIX_C_SOURCE 200809L /* stat */
#include <errno.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/step_internal.h"

/* Files beyond this are refused rather than parsed: node offsets are ints, and the parsed form
 * takes several times the file size. */
static const long MAX_FILE_BYTES = 1L << 30;

/* Relative to the model size: the fitting tolerance of computed pcurves when the file states
 * no uncertainty. */
static const double DEFAULT_RELATIVE_TOL = 1e-6;

/* Replaces pcurves that miss their edges and computes the missing ones (most files give none).
 * A coedge whose pcurve cannot be fitted (an edge through a pole) is left without one: the
 * 3D B-rep is still whole, and the validator says which coedges lack pcurves. */
static cb_status complete_pcurves(cb_topo_body *b, cb_error *err)
{
    double tol = b->tol;
    if (!(tol > 0)) {
        cb_aabb box;
        cb_topo_body_edge_box(&box, b);
        double d[3] = {box.hi[0] - box.lo[0], box.hi[1] - box.lo[1], box.hi[2] - box.lo[2]};
        tol = DEFAULT_RELATIVE_TOL * fmax(cb_vec3_norm(d), 1e-300);
    }
    int dropped;
    cb_error local;
    cb_status st = cb_topo_repair_pcurves(b, tol, 9, &dropped, &local);
    if (st == CB_ERR_NUMERIC)
        return CB_OK;
    if (st)
        cb_error_set(err, st, "%s", local.msg);
    return st;
}

/* Turns the closed shells of solids that a file writes inside out: an outer shell whose
 * enclosed volume is negative, a void's whose is positive (brep/topo.h, cb_topo_shell_volume
 * with 64 columns: a few percent, plenty for a sign), as Open CASCADE's reader does
 * (ShapeFix_Solid). A shell whose volume cannot be decided is left as written (validation
 * says why). */
static cb_status orient_shells(cb_topo_body *b, cb_error *err)
{
    int turned = 0;
    for (int k = 0; k < b->n_shells; k++) {
        const cb_topo_shell *sh = &b->shells[k];
        if (sh->solid < 0 || !sh->closed)
            continue;
        double vol;
        cb_error local;
        cb_status st = cb_topo_shell_volume(&vol, b, k, 64, b->tol, &local);
        if (st == CB_ERR_NOMEM)
            return cb_error_set(err, st, "%s", local.msg);
        int void_shell = b->solids[sh->solid].first != k;
        if (!st && (void_shell ? vol > 0 : vol < 0)) {
            cb_topo_shell_reverse(b, k);
            turned = 1;
        }
    }
    return turned ? cb_topo_body_index(b, err) : CB_OK;
}

void cb_step_options_init(cb_step_options *opt)
{
    opt->max_edge_tol_rel = CB_STEP_MAX_EDGE_TOL_REL;
}

static cb_status read_loaded(cb_topo_body **out, step_file *f, const cb_step_options *opt,
                             cb_step_stats *stats)
{
    cb_step_options defaults;
    cb_step_stats unused;
    if (!opt) {
        cb_step_options_init(&defaults);
        opt = &defaults;
    }
    if (!stats)
        stats = &unused;
    memset(stats, 0, sizeof *stats);
    cb_status st = step_parse(f);
    if (!st) {
        f->state = calloc((size_t)f->n_recs + 1, 1);
        f->memo = malloc(((size_t)f->n_recs + 1) * sizeof *f->memo);
        f->memo_kind = calloc((size_t)f->n_recs + 1, 1);
        f->body = cb_topo_body_new();
        if (!f->state || !f->memo || !f->memo_kind || !f->body)
            st = cb_error_set(f->err, CB_ERR_NOMEM, "%s: out of memory", f->path);
    }
    if (!st)
        st = step_map_body(f);
    if (!st && (st = cb_topo_close_faces(f->body, f->body->tol, NULL, f->err)))
        cb_error_prefix(f->err, "%s: ", f->path);
    if (!st)
        st = cb_topo_body_index(f->body, f->err);
    if (!st)
        st = complete_pcurves(f->body, f->err);
    if (!st)
        st = orient_shells(f->body, f->err);
    if (!st)
        st = step_fit_edge_tols(f->body, opt->max_edge_tol_rel, stats, f->err);
    if (st) {
        memset(stats, 0, sizeof *stats);
        cb_topo_body_free(f->body);
        f->body = NULL;
    }
    *out = f->body;
    step_file_free(f);
    return st;
}

cb_status cb_step_read_buffer(cb_topo_body **out, const char *data, size_t len, const char *name,
                              cb_error *err)
{
    return cb_step_read_buffer_opt(out, data, len, name, NULL, NULL, err);
}

cb_status cb_step_read(cb_topo_body **out, const char *path, cb_error *err)
{
    return cb_step_read_opt(out, path, NULL, NULL, err);
}

cb_status cb_step_read_buffer_opt(cb_topo_body **out, const char *data, size_t len,
                                  const char *name, const cb_step_options *opt,
                                  cb_step_stats *stats, cb_error *err)
{
    if (stats)
        memset(stats, 0, sizeof *stats);
    cb_error local;
    step_file f = {.path = name, .err = err ? err : &local};
    *out = NULL;
    if (len > (size_t)MAX_FILE_BYTES)
        return cb_error_set(f.err, CB_ERR_UNSUPPORTED,
                            "%s: %zu bytes, more than the %ld the "
                            "reader accepts",
                            name, len, MAX_FILE_BYTES);
    if (!(f.buf = malloc(len + 1)))
        return cb_error_set(f.err, CB_ERR_NOMEM, "%s: no memory for %zu bytes", name, len);
    memcpy(f.buf, data, len);
    f.buf[len] = '\0';
    f.len = len;
    return read_loaded(out, &f, opt, stats);
}

cb_status cb_step_read_opt(cb_topo_body **out, const char *path, const cb_step_options *opt,
                           cb_step_stats *stats, cb_error *err)
{
    if (stats)
        memset(stats, 0, sizeof *stats);
    cb_error local;
    step_file f = {.path = path, .err = err ? err : &local};
    *out = NULL;
    /* What the path is, asked before opening it: fopen opens a directory (ftell then reports
     * LONG_MAX for it), and opening a FIFO blocks. */
    struct stat sb;
    if (stat(path, &sb))
        return cb_error_set(f.err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(sb.st_mode))
        return cb_error_set(f.err, CB_ERR_IO, "%s: %s", path,
                            S_ISDIR(sb.st_mode) ? "is a directory" : "not a regular file");
    FILE *in = fopen(path, "rb");
    if (!in)
        return cb_error_set(f.err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    long size = -1;
    if (!fseek(in, 0, SEEK_END))
        size = ftell(in);
    if (size < 0 || fseek(in, 0, SEEK_SET)) {
        int e = errno;
        fclose(in);
        return cb_error_set(f.err, CB_ERR_IO, "%s: cannot read: %s", path, strerror(e));
    }
    if (size > MAX_FILE_BYTES) {
        fclose(in);
        return cb_error_set(f.err, CB_ERR_UNSUPPORTED,
                            "%s: %ld bytes, more than the %ld the "
                            "reader accepts",
                            path, size, MAX_FILE_BYTES);
    }
    if (!(f.buf = malloc((size_t)size + 1))) {
        fclose(in);
        return cb_error_set(f.err, CB_ERR_NOMEM, "%s: no memory for %ld bytes", path, size);
    }
    size_t got = fread(f.buf, 1, (size_t)size, in);
    int bad = ferror(in);
    fclose(in);
    if (bad || got != (size_t)size) {
        free(f.buf);
        return cb_error_set(f.err, CB_ERR_IO, "%s: read error", path);
    }
    f.buf[got] = '\0';
    f.len = got;
    return read_loaded(out, &f, opt, stats);
}
