/* bench_parts — the real-parts class of the randomized corpus (issue 22): Booleans of real CAD
 * parts against copies of themselves moved by random rigid motions, run through Colibri and,
 * where given, Open CASCADE, scored by the corpus's rules (bench/corpus/corpus.h) against a
 * truth that uses no Boolean code.
 *
 * Parts, chosen by rule (none by hand):
 *   - every STEP file of SHARED/models that Colibri reads as a valid solid (cb_topo_validate at
 *     the file's tolerance) whose volume integrates (cb_mass_body);
 *   - from SHARED/corpus/step, in file-name order, the first --corpus-parts files (default 6)
 *     that Open CASCADE's reference (SHARED/corpus/occt-reference.json) lists as one valid solid
 *     with a volume, with --faces LO HI faces (default 8 to 60) of which at least one is neither
 *     a plane, a cylinder nor a cone (a freeform, toroidal, spherical or swept face), whose name
 *     is not already among the models, and that Colibri reads valid with a volume within 1e-6
 *     (relative) of OCCT's (converted from mm^3 to the file's unit).
 * Each part is listed with the reason when it is not taken.
 *
 * Cases: for each part and each of --draws K draws (default 3), a rigid motion drawn from a
 * seeded generator keyed by the part's file name, the seed and the draw (the same motion
 * whatever other parts are run): a rotation about the part's centroid by an angle uniform in
 * [--angle LO HI] degrees (default 5 to 60) about the axis of a uniform random unit quaternion,
 * then a translation by a fraction uniform in [--shift LO HI] (default 0.1 to 0.4) of the part's
 * edge-box diagonal along a uniform random direction. A motion is drawn again (up to 32 times)
 * while a coarse estimate (40 x 40 lines) finds the copy overlapping the part by less than 2% of
 * its volume: thin parts shifted along their normal would give no test. The moved copy B is
 * written by Colibri's STEP writer (cb_step_write) and read back, so that both tools get the
 * same two files: A the part's own file, B the written copy.
 *
 * Truth, independent of the Boolean code: V(A) and V(B) by the mass integration of the operands
 * (cb_mass_body, about 1e-9 relative; V(B) from the file read back), V(A n B) by
 * cb_model_overlap_estimate (models/models.h: --grid N x N vertical lines through both solids,
 * default 600, its cost N^2 ray casts per face; its standard deviation sigma); then
 * V(A u B) = V(A) + V(B) - V(A n B) and V(A - B) = V(A) - V(A n B), each with the bar
 * 4 sigma + 1e-6 |truth| + 1e-9 (V(A) + V(B)). The estimate's lines are vertical: both solids
 * are estimated in a frame turned by a random rotation (volumes do not change), so that faces
 * axis-aligned in the files are not grazed along their length, and in another frame (up to 4)
 * where every line of a cell grazes, touches an edge within the body's tolerance or misses a
 * crossing. The estimate's own V(A), V(B) are compared with the mass integration's and shown in
 * sigmas (zA, zB: a check of the estimator; a line that missed crossings would show there).
 *
 * Runs: union, intersection and A - B of every case, `colibri bool OP A B -o X.stl --json R.json
 * --quiet` and, with --occt, `occt_bool 1 A B OP`, each in a process group of its own killed
 * at --timeout seconds (default 60; bench/corpus/corpus_run.h). Verdicts as in bench_corpus:
 * pass, refused (with the tool's reason), WRONG (reported success, but the result is not
 * valid, its mesh is open or crosses itself, or its volume is off the truth by more than the
 * bar), crash, timeout.
 *
 * Output: a row per run, a table per part (counts of each verdict for both tools, median times
 * and their ratio C/O over the runs both passed), totals, every non-pass with its reason and
 * the refusal reasons by count; with --json, every run.
 *
 * Usage: bench_parts [--shared DIR] [--colibri PATH] [--occt PATH] [--draws K]
 *                    [--corpus-parts N] [--faces LO HI] [--angle LO HI] [--shift LO HI]
 *                    [--grid N] [--seed S] [--timeout S] [--threads N] [--only REGEX]
 *                    [--keep DIR] [--json OUT]
 *   --shared  the shared data folder (default ../shared)
 *   --only    only parts whose file name matches the extended regular expression
 *   --keep    write the moved copies there (default: a temporary folder, removed) */
#define _DEFAULT_SOURCE
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <regex.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench/corpus/corpus.h"
#include "bench/corpus/corpus_run.h"
#include "brep/geom.h"
#include "brep/mass.h"
#include "brep/topo.h"
#include "io/json.h"
#include "io/step.h"
#include "io/step_write.h"
#include "models/models.h"

/* Relative accuracy asked of the operands' volumes: far below any bar used here. */
#define PARTS_MASS_REL_TOL 1e-9
/* A corpus file is taken when Colibri's volume is within this of OCCT's, relative. */
#define PARTS_VOLUME_AGREE 1e-6
/* Sigmas of the overlap estimate in the bar. */
#define PARTS_BAR_SIGMAS 4.0

typedef struct {
    char path[1024], name[256];
    int faces;
    double volume, unit_mm, centroid[3], diag;
} part;

typedef struct {
    int part, draw;
    char b_path[1200];
    double angle_deg, axis[3], shift[3];
    double va, vb, vi, sigma;  /* truth: V(A), V(B) by mass; V(A n B) estimated, its sigma */
    double za, zb;             /* the estimate's V(A), V(B) off the mass integration, sigmas */
    double t_estimate;         /* seconds, coarse and fine estimates */
    int attempts;              /* draws until one overlapped */
    char error[512];           /* why the case could not be made ("" when it was) */
} parts_case;

typedef corpus_side side;

typedef struct {
    int case_index, op;
    double truth, bar;
    side c, o;
} run_result;

/* ---------------------------------------------------------------- random motions ----------- */

static uint64_t splitmix(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double uniform(uint64_t *s)
{
    return (double)(splitmix(s) >> 11) * 0x1p-53;
}

/* A standard normal number (Box-Muller). */
static double normal(uint64_t *s)
{
    double u = uniform(s), v = uniform(s);
    return sqrt(-2 * log1p(-u)) * cos(2 * 3.14159265358979323846 * v);
}

/* A uniform unit vector: the normalised vector part of a uniform unit quaternion (four
 * normals normalised) is uniform on the sphere. */
static void random_direction(double d[3], uint64_t *s)
{
    for (;;) {
        double q[4], n = 0;
        for (int k = 0; k < 4; k++) {
            q[k] = normal(s);
            n += q[k] * q[k];
        }
        double m = sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (m > 1e-6 * sqrt(n)) {
            for (int k = 0; k < 3; k++)
                d[k] = q[k + 1] / m;
            return;
        }
    }
}

/* FNV-1a of a string: the part's key, so that its draws do not depend on the other parts. */
static uint64_t name_hash(const char *s)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 0x100000001b3ull;
    return h;
}

/* ---------------------------------------------------------------- parts -------------------- */

/* Reads path as a valid solid: its faces, volume, centroid, unit and edge-box diagonal; 0, or
 * -1 with the reason. */
static int part_load(part *p, const char *path, char *why, size_t n)
{
    memset(p, 0, sizeof *p);
    snprintf(p->path, sizeof p->path, "%s", path);
    const char *slash = strrchr(path, '/');
    snprintf(p->name, sizeof p->name, "%s", slash ? slash + 1 : path);
    cb_error err;
    cb_error_clear(&err);
    cb_topo_body *b = NULL;
    if (cb_step_read(&b, path, &err)) {
        snprintf(why, n, "not read: %.400s", err.msg);
        return -1;
    }
    int rc = -1;
    cb_topo_report r;
    cb_topo_report_init(&r);
    cb_mass_props m;
    memset(&m, 0, sizeof m);
    if (b->n_solids < 1) {
        snprintf(why, n, "no solid (%d shells)", b->n_shells);
    } else if (cb_topo_validate(&r, b, b->tol, 9, &err)) {
        snprintf(why, n, "validation failed: %s", err.msg);
    } else if (r.n) {
        snprintf(why, n, "not valid: %d problems, first: %s", r.n, r.items[0]);
    } else if (cb_mass_body(&m, b, PARTS_MASS_REL_TOL, NULL, &err)) {
        snprintf(why, n, "volume not integrated: %s", err.msg);
    } else if (!(m.volume > 0)) {
        snprintf(why, n, "volume %g", m.volume);
    } else {
        cb_aabb box;
        cb_topo_body_edge_box(&box, b);
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            d2 += (box.hi[k] - box.lo[k]) * (box.hi[k] - box.lo[k]);
            p->centroid[k] = m.centroid[k];
        }
        p->diag = sqrt(d2);
        p->faces = b->n_faces;
        p->volume = m.volume;
        p->unit_mm = b->length_unit_mm > 0 ? b->length_unit_mm : 1;
        rc = 0;
    }
    cb_topo_report_clear(&r);
    cb_topo_body_free(b);
    return rc;
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The STEP files of dir (.step, .stp, any case), sorted by name: a new array of new strings. */
static char **step_files(const char *dir, int *n)
{
    *n = 0;
    DIR *d = opendir(dir);
    if (!d)
        return NULL;
    char **v = NULL;
    int cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *dot = strrchr(e->d_name, '.');
        if (!dot || (strcasecmp(dot, ".step") && strcasecmp(dot, ".stp")))
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 64;
            char **m = realloc(v, (size_t)cap * sizeof *v);
            if (!m)
                break;
            v = m;
        }
        v[(*n)++] = strdup(e->d_name);
    }
    closedir(d);
    if (v)
        qsort(v, (size_t)*n, sizeof *v, cmp_name);
    return v;
}

/* The whole of a file as a new string (NULL when it cannot be read). */
static char *read_all(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = len >= 0 ? malloc((size_t)len + 1) : NULL;
    if (s && fread(s, 1, (size_t)len, f) != (size_t)len) {
        free(s);
        s = NULL;
    }
    if (s)
        s[len] = 0;
    fclose(f);
    return s;
}

/* OCCT's reference entry of file `name` (its text up to the next entry) into out; 0 when the
 * reference has none. */
static int reference_entry(char *out, size_t n, const char *ref, const char *name)
{
    char pat[320];
    snprintf(pat, sizeof pat, "\"file\": \"%s\"", name);
    const char *p = strstr(ref, pat);
    if (!p)
        return 0;
    const char *end = strstr(p + strlen(pat), "\"file\":");
    size_t len = end ? (size_t)(end - p) : strlen(p);
    snprintf(out, n, "%.*s", (int)(len < n - 1 ? len : n - 1), p);
    return 1;
}

/* Whether OCCT's surface types of an entry include one that is not a plane, cylinder or cone. */
static int has_curved_face(const char *entry)
{
    const char *p = corpus_json_value(entry, "surface_types");
    if (!p || *p != '{')
        return 0;
    const char *end = strchr(p, '}');
    for (const char *q = strchr(p, '"'); q && end && q < end; q = strchr(q, '"')) {
        const char *close = strchr(q + 1, '"');
        if (!close)
            return 0;
        size_t len = (size_t)(close - q - 1);
        static const char *const simple[] = {"Plane", "CylindricalSurface", "ConicalSurface"};
        int known = 0;
        for (int k = 0; k < 3; k++)
            known |= len == strlen(simple[k]) && !strncmp(q + 1, simple[k], len);
        if (!known)
            return 1;
        q = strchr(close, ',');
        if (!q)
            break;
    }
    return 0;
}

/* ---------------------------------------------------------------- cases -------------------- */

typedef struct {
    double angle[2], shift[2];
    uint64_t seed;
    int grid, threads;
    const char *dir; /* where the moved copies go */
} case_opts;

/* Reads path moved by x (NULL: as it is); NULL with err set when it cannot be read. */
static cb_topo_body *read_moved(const char *path, const cb_xform *x, cb_error *err)
{
    cb_topo_body *b = NULL;
    if (cb_step_read(&b, path, err))
        return NULL;
    if (x)
        cb_topo_body_transform(b, x);
    return b;
}

/* V(A n B) of the coarse estimate below which a draw is taken again: a copy moved off the part
 * (a thin part shifted along its normal) would give an empty intersection, no test. */
#define PARTS_MIN_OVERLAP 0.02
/* Draws per case before giving up on an overlapping one, and the coarse estimate's grid. */
#define PARTS_MAX_ATTEMPTS 32
#define PARTS_COARSE_GRID 40
/* Frames an estimate is tried in before it is given up. */
#define PARTS_FRAMES 4

/* cb_model_overlap_estimate of the solid in file pa and that in file pb moved by xb (NULL: as
 * it is). The estimate's lines are vertical; to keep them off faces that are axis-aligned in
 * the files (vertical planes and cylinders, grazed along their length), both solids are turned
 * by a random rotation of their own first (rigid motions keep the volumes), and where every
 * line of a cell still grazes or touches an edge, the estimate is taken again in another
 * frame, up to PARTS_FRAMES. */
static cb_status estimate_framed(cb_overlap_estimate *e, const char *pa, const char *pb,
                                 const cb_xform *xb, int grid, int threads, uint64_t *s,
                                 cb_error *err)
{
    cb_status st = CB_OK;
    for (int f = 0; f < PARTS_FRAMES; f++) {
        double axis[3], origin[3] = {0, 0, 0};
        random_direction(axis, s);
        cb_xform frame, fx;
        cb_xform_rotation(&frame, origin, axis, 2 * 3.14159265358979323846 * uniform(s));
        if (xb)
            cb_xform_compose(&fx, &frame, xb);
        else
            fx = frame;
        cb_topo_body *a = read_moved(pa, &frame, err), *b = a ? read_moved(pb, &fx, err) : NULL;
        st = b ? cb_model_overlap_estimate(e, a, b, grid, threads, err) : CB_ERR_IO;
        cb_topo_body_free(a);
        cb_topo_body_free(b);
        if (st != CB_ERR_NUMERIC)
            break;
    }
    return st;
}

/* Draws case pc of part p, writes and reads back the moved copy and estimates the overlap. */
static void case_make(parts_case *pc, const part *p, int part_index, int draw,
                      const case_opts *co)
{
    memset(pc, 0, sizeof *pc);
    pc->part = part_index;
    pc->draw = draw;
    uint64_t s = name_hash(p->name) ^ (co->seed * 0x9e3779b97f4a7c15ull) ^
                 ((uint64_t)draw * 0xd1b54a32d192ed03ull);
    cb_xform x;
    cb_error err;
    cb_error_clear(&err);
    cb_overlap_estimate e;
    double t0 = now_s();
    int found = 0;
    char last[512] = "";
    for (int attempt = 0; attempt < PARTS_MAX_ATTEMPTS && !found; attempt++) {
        random_direction(pc->axis, &s);
        pc->angle_deg = co->angle[0] + (co->angle[1] - co->angle[0]) * uniform(&s);
        double dir[3], frac = co->shift[0] + (co->shift[1] - co->shift[0]) * uniform(&s);
        random_direction(dir, &s);
        for (int k = 0; k < 3; k++)
            pc->shift[k] = frac * p->diag * dir[k];
        cb_xform r, t;
        cb_xform_rotation(&r, p->centroid, pc->axis,
                          pc->angle_deg * 3.14159265358979323846 / 180);
        cb_xform_translation(&t, pc->shift);
        cb_xform_compose(&x, &t, &r);
        pc->attempts = attempt + 1;
        cb_status st = estimate_framed(&e, p->path, p->path, &x, PARTS_COARSE_GRID, co->threads,
                                       &s, &err);
        if (st)
            snprintf(last, sizeof last, "; last: %.400s", err.msg);
        found = !st && e.volume_ab >= PARTS_MIN_OVERLAP * p->volume;
    }
    if (!found) {
        snprintf(pc->error, sizeof pc->error,
                 "no draw of %d overlaps by %g of V(A) (coarse estimate)%.400s",
                 PARTS_MAX_ATTEMPTS, PARTS_MIN_OVERLAP, last);
        return;
    }

    char stem[256];
    snprintf(stem, sizeof stem, "%.*s", (int)strcspn(p->name, "."), p->name);
    snprintf(pc->b_path, sizeof pc->b_path, "%s/%s_d%d.step", co->dir, stem, draw);
    cb_topo_body *b = read_moved(p->path, &x, &err);
    cb_status st = b ? cb_step_write(b, pc->b_path, stem, &err) : CB_ERR_IO;
    cb_topo_body_free(b);
    if (st) {
        snprintf(pc->error, sizeof pc->error, "moved copy not written: %.400s", err.msg);
        return;
    }
    part back;
    char why[600];
    if (part_load(&back, pc->b_path, why, sizeof why)) {
        snprintf(pc->error, sizeof pc->error, "moved copy read back: %.400s", why);
        return;
    }
    pc->va = p->volume;
    pc->vb = back.volume;
    /* The fine estimate takes B as the tools get it: the file read back. */
    if (estimate_framed(&e, p->path, pc->b_path, NULL, co->grid, co->threads, &s, &err)) {
        snprintf(pc->error, sizeof pc->error, "%.400s", err.msg); /* "overlap estimate: ..." */
    } else {
        pc->vi = e.volume_ab;
        pc->sigma = e.sigma_ab;
        pc->za = e.sigma_a > 0 ? (e.volume_a - pc->va) / e.sigma_a : NAN;
        pc->zb = e.sigma_b > 0 ? (e.volume_b - pc->vb) / e.sigma_b : NAN;
    }
    pc->t_estimate = now_s() - t0;
}

static double case_truth(const parts_case *c, int op)
{
    return op == 0 ? c->va + c->vb - c->vi : op == 1 ? c->vi : c->va - c->vi;
}

static double case_bar(const parts_case *c, int op)
{
    return PARTS_BAR_SIGMAS * c->sigma + 1e-6 * fabs(case_truth(c, op)) + 1e-9 * (c->va + c->vb);
}

/* ---------------------------------------------------------------- tables ------------------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    if (n == 0)
        return NAN;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

typedef struct {
    int n, c[5], o[5];
    int timed;
    double ct_med, ot_med;
} tally;

/* Tallies the runs of part (-1: every part) and operation (-1: every one). */
static tally tally_of(const run_result *r, int nr, const parts_case *cases, int part_index,
                      int op, int occt, double *sc, double *so)
{
    tally t;
    memset(&t, 0, sizeof t);
    int m = 0;
    for (int k = 0; k < nr; k++) {
        if ((part_index >= 0 && cases[r[k].case_index].part != part_index) ||
            (op >= 0 && r[k].op != op))
            continue;
        t.n++;
        t.c[r[k].c.v]++;
        t.o[r[k].o.v]++;
        if (r[k].c.v == CORPUS_PASS && isfinite(r[k].c.o.time_s) &&
            (!occt || (r[k].o.v == CORPUS_PASS && isfinite(r[k].o.o.time_s)))) {
            sc[m] = r[k].c.o.time_s;
            so[m] = r[k].o.o.time_s;
            m++;
        }
    }
    t.timed = m;
    t.ct_med = median(sc, m);
    t.ot_med = median(so, m);
    return t;
}

static void print_tally(const char *label, const tally *t, int occt)
{
    printf("%-34s %4d | %4d %4d %4d %4d %4d |", label, t->n, t->c[0], t->c[1], t->c[2], t->c[3],
           t->c[4]);
    if (occt) {
        printf(" %4d %4d %4d %4d %4d | %4d", t->o[0], t->o[1], t->o[2], t->o[3], t->o[4],
               t->timed);
        if (t->timed)
            printf(" %8.3f %8.3f %6.2f", t->ct_med, t->ot_med,
                   t->ot_med > 0 ? t->ct_med / t->ot_med : NAN);
        else
            printf(" %8s %8s %6s", "-", "-", "-");
    } else if (t->timed) {
        printf(" %4d %8.3f", t->timed, t->ct_med);
    } else {
        printf(" %4d %8s", 0, "-");
    }
    printf("\n");
}

typedef struct {
    char reason[400];
    int count;
    char example[160];
} reason_count;

static int cmp_reason(const void *a, const void *b)
{
    const reason_count *x = a, *y = b;
    return y->count - x->count;
}

/* Refusal reasons of one tool (0 Colibri, 1 OCCT) by count, numbers and file names stripped. */
static void print_reasons(const run_result *r, int nr, const parts_case *cases, const part *parts,
                          int tool)
{
    reason_count *rc = calloc((size_t)nr + 1, sizeof *rc);
    int n = 0;
    for (int k = 0; rc && k < nr; k++) {
        const side *s = tool ? &r[k].o : &r[k].c;
        if (s->v != CORPUS_REFUSED)
            continue;
        const parts_case *pc = cases + r[k].case_index;
        corpus_case cc;
        memset(&cc, 0, sizeof cc);
        snprintf(cc.a, sizeof cc.a, "%.120s", parts[pc->part].name);
        const char *slash = strrchr(pc->b_path, '/');
        snprintf(cc.b, sizeof cc.b, "%.120s", slash ? slash + 1 : pc->b_path);
        char cls[400];
        corpus_reason_class(cls, sizeof cls, s->why, &cc);
        int j = 0;
        while (j < n && strcmp(rc[j].reason, cls))
            j++;
        if (j == n) {
            snprintf(rc[j].reason, sizeof rc[j].reason, "%s", cls);
            snprintf(rc[j].example, sizeof rc[j].example, "%.120s d%d %s", parts[pc->part].name,
                     pc->draw, corpus_op_names[r[k].op]);
            n++;
        }
        rc[j].count++;
    }
    if (!rc)
        return;
    qsort(rc, (size_t)n, sizeof *rc, cmp_reason);
    printf("\n%s refusals by reason (numbers as #; count, reason, first run):\n",
           tool ? "OCCT" : "Colibri");
    for (int j = 0; j < n; j++)
        printf("%5d  %s  [%s]\n", rc[j].count, rc[j].reason, rc[j].example);
    free(rc);
}

/* ---------------------------------------------------------------- main --------------------- */

static int usage(void)
{
    fprintf(stderr, "usage: bench_parts [--shared DIR] [--colibri PATH] [--occt PATH] [--draws K] "
                    "[--corpus-parts N] [--faces LO HI] [--angle LO HI] [--shift LO HI] "
                    "[--grid N] [--seed S] [--timeout S] [--threads N] [--only REGEX] "
                    "[--keep DIR] [--json OUT]\n");
    return 2;
}

int main(int argc, char **argv)
{
    run_opts ro = {"build/cli/colibri", NULL, NULL, NULL, 60, 0};
    case_opts co = {{5, 60}, {0.1, 0.4}, 1, 600, 0, NULL};
    const char *shared = "../shared", *json_path = NULL, *only = NULL, *keep = NULL;
    int draws = 3, corpus_parts = 6, faces_lo = 8, faces_hi = 60;
    for (int k = 1; k < argc; k++) {
        const char *a = argv[k];
        int more = argc - k - 1;
        if (!strcmp(a, "--shared") && more >= 1)
            shared = argv[++k];
        else if (!strcmp(a, "--colibri") && more >= 1)
            ro.colibri = argv[++k];
        else if (!strcmp(a, "--occt") && more >= 1)
            ro.occt = argv[++k];
        else if (!strcmp(a, "--draws") && more >= 1)
            draws = atoi(argv[++k]);
        else if (!strcmp(a, "--corpus-parts") && more >= 1)
            corpus_parts = atoi(argv[++k]);
        else if (!strcmp(a, "--faces") && more >= 2) {
            faces_lo = atoi(argv[++k]);
            faces_hi = atoi(argv[++k]);
        } else if (!strcmp(a, "--angle") && more >= 2) {
            co.angle[0] = atof(argv[++k]);
            co.angle[1] = atof(argv[++k]);
        } else if (!strcmp(a, "--shift") && more >= 2) {
            co.shift[0] = atof(argv[++k]);
            co.shift[1] = atof(argv[++k]);
        } else if (!strcmp(a, "--grid") && more >= 1)
            co.grid = atoi(argv[++k]);
        else if (!strcmp(a, "--seed") && more >= 1)
            co.seed = strtoull(argv[++k], NULL, 10);
        else if (!strcmp(a, "--timeout") && more >= 1)
            ro.timeout = atof(argv[++k]);
        else if (!strcmp(a, "--threads") && more >= 1)
            ro.threads = co.threads = atoi(argv[++k]);
        else if (!strcmp(a, "--only") && more >= 1)
            only = argv[++k];
        else if (!strcmp(a, "--keep") && more >= 1)
            keep = argv[++k];
        else if (!strcmp(a, "--json") && more >= 1)
            json_path = argv[++k];
        else
            return usage();
    }
    if (draws < 1 || corpus_parts < 0 || !(ro.timeout > 0) || co.grid < 2 || co.grid % 2 ||
        co.grid > 20000 || !(co.angle[0] <= co.angle[1]) || !(co.shift[0] <= co.shift[1]))
        return usage();
    if (access(ro.colibri, X_OK)) {
        fprintf(stderr, "bench_parts: %s is not an executable (--colibri)\n", ro.colibri);
        return 2;
    }
    if (ro.occt && access(ro.occt, X_OK)) {
        fprintf(stderr, "bench_parts: %s is not an executable (--occt)\n", ro.occt);
        return 2;
    }
    regex_t re;
    if (only && regcomp(&re, only, REG_EXTENDED | REG_NOSUB)) {
        fprintf(stderr, "bench_parts: bad regular expression '%s'\n", only);
        return 2;
    }
    char tmp[] = "/tmp/colibri_parts_XXXXXX"; /* mkdtemp's template */
    if (!mkdtemp(tmp)) {
        fprintf(stderr, "bench_parts: cannot make a temporary directory\n");
        return 1;
    }
    ro.tmp = tmp;
    co.dir = keep ? keep : tmp;
    if (keep && mkdir(keep, 0755) && errno != EEXIST) {
        fprintf(stderr, "bench_parts: cannot make %s: %s\n", keep, strerror(errno));
        return 1;
    }
    double t_start = now_s();

    /* The parts. */
    part *parts = calloc(256, sizeof *parts);
    int np = 0;
    char dir[1024], path[1400], why[700];
    printf("Parts (rule in bench/bench_parts.c):\n");
    snprintf(dir, sizeof dir, "%s/models", shared);
    int nm = 0;
    char **models = step_files(dir, &nm);
    for (int i = 0; parts && i < nm && np < 256; i++) {
        if (only && regexec(&re, models[i], 0, NULL, 0))
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, models[i]);
        if (part_load(parts + np, path, why, sizeof why))
            printf("  models/%-40s not taken: %s\n", models[i], why);
        else
            np++;
    }
    snprintf(dir, sizeof dir, "%s/corpus", shared);
    snprintf(path, sizeof path, "%s/occt-reference.json", dir);
    char *ref = read_all(path);
    if (!ref && corpus_parts > 0)
        printf("  corpus: %s not read, no corpus parts\n", path);
    snprintf(dir, sizeof dir, "%s/corpus/step", shared);
    int nf = 0;
    char **files = ref && corpus_parts > 0 ? step_files(dir, &nf) : NULL;
    static char entry[16384];
    for (int i = 0, taken = 0; parts && i < nf && taken < corpus_parts && np < 256; i++) {
        if (only && regexec(&re, files[i], 0, NULL, 0))
            continue;
        int dup = 0;
        for (int j = 0; j < nm; j++)
            dup |= !strcmp(files[i], models[j]);
        if (dup || !reference_entry(entry, sizeof entry, ref, files[i]))
            continue;
        double solids = corpus_json_number(entry, "solids"), nfaces = corpus_json_number(entry, "faces");
        double vocc = corpus_json_number(entry, "volume");
        if (solids != 1 || corpus_json_bool(entry, "valid") != 1 || !isfinite(vocc) ||
            !(nfaces >= faces_lo && nfaces <= faces_hi) || !has_curved_face(entry))
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        part *p = parts + np;
        if (part_load(p, path, why, sizeof why)) {
            printf("  corpus/step/%-36s not taken: %s\n", files[i], why);
            continue;
        }
        double u3 = p->unit_mm * p->unit_mm * p->unit_mm, vo = vocc / u3;
        if (fabs(p->volume - vo) > PARTS_VOLUME_AGREE * fabs(vo)) {
            printf("  corpus/step/%-36s not taken: volume %.10g, OCCT's %.10g (%.2e relative)\n",
                   files[i], p->volume, vo, fabs(p->volume - vo) / fabs(vo));
            continue;
        }
        np++;
        taken++;
    }
    for (int i = 0; i < np; i++)
        printf("  %-48s %3d faces, volume %.10g (unit %g mm), diagonal %.4g\n", parts[i].name,
               parts[i].faces, parts[i].volume, parts[i].unit_mm, parts[i].diag);
    if (np == 0) {
        fprintf(stderr, "bench_parts: no part\n");
        return 1;
    }

    /* The cases and their truths. */
    parts_case *cases = calloc((size_t)np * (size_t)draws, sizeof *cases);
    run_result *r = calloc((size_t)np * (size_t)draws * 3, sizeof *r);
    double *sc = malloc((size_t)np * (size_t)draws * 3 * sizeof *sc);
    double *so = malloc((size_t)np * (size_t)draws * 3 * sizeof *so);
    if (!cases || !r || !sc || !so) {
        fprintf(stderr, "bench_parts: out of memory\n");
        return 1;
    }
    int nc = 0, nr = 0, occt = ro.occt != NULL;
    int tty = isatty(STDERR_FILENO);
    printf("\nCases: rotation about the centroid by [%g, %g] deg, shift [%g, %g] of the diagonal, "
           "seed %llu; truth V(A n B) by %d x %d lines (bar %g sigma + 1e-6 |truth| + 1e-9 "
           "(V(A) + V(B))); time limit %g s per run\n",
           co.angle[0], co.angle[1], co.shift[0], co.shift[1], (unsigned long long)co.seed,
           co.grid, co.grid, PARTS_BAR_SIGMAS, ro.timeout);
    printf("%-24s %2s %3s %6s %-22s %-12s %14s %9s %9s %6s %6s %6s | %-7s %14s %8s", "part", "d",
           "try", "angle", "axis", "op", "truth", "bar", "sigma/V", "zA", "zB", "est s",
           "Colibri", "volume", "s");
    if (occt)
        printf(" | %-7s %14s %8s", "OCCT", "volume", "s");
    printf("\n");
    for (int i = 0; i < np; i++)
        for (int d = 0; d < draws; d++) {
            parts_case *pc = cases + nc++;
            if (tty)
                fprintf(stderr, "bench_parts: %.0f s: %s draw %d: estimate          \r",
                        now_s() - t_start, parts[i].name, d);
            case_make(pc, parts + i, i, d, &co);
            char axis[64];
            snprintf(axis, sizeof axis, "(%.3f,%.3f,%.3f)", pc->axis[0], pc->axis[1], pc->axis[2]);
            if (pc->error[0]) {
                printf("%-24.24s %2d %3d %6.2f %-22s case not made: %s\n", parts[i].name, d,
                       pc->attempts, pc->angle_deg, axis, pc->error);
                continue;
            }
            for (int op = 0; op < 3; op++) {
                run_result *x = r + nr++;
                x->case_index = nc - 1;
                x->op = op;
                x->truth = case_truth(pc, op);
                x->bar = case_bar(pc, op);
                if (tty)
                    fprintf(stderr, "bench_parts: %.0f s: %s draw %d: %s          \r",
                            now_s() - t_start, parts[i].name, d, corpus_op_names[op]);
                run_colibri(&x->c.o, parts[i].path, pc->b_path, op, &ro);
                x->c.v = corpus_score_truth(&x->c.o, x->truth, x->bar, 0, x->c.why,
                                            sizeof x->c.why);
                if (occt) {
                    run_occt(&x->o.o, parts[i].path, pc->b_path, op, &ro);
                    /* OCCT's reader converts to millimetres; Colibri keeps the file's unit. */
                    double u3 = parts[i].unit_mm * parts[i].unit_mm * parts[i].unit_mm;
                    x->o.o.volume /= u3;
                    x->o.v = corpus_score_truth(&x->o.o, x->truth, x->bar, 0, x->o.why,
                                                sizeof x->o.why);
                } else {
                    corpus_outcome_init(&x->o.o);
                    x->o.v = CORPUS_REFUSED;
                    snprintf(x->o.why, sizeof x->o.why, "not run");
                }
                printf("%-24.24s %2d %3d %6.2f %-22s %-12s %14.8g %9.2e %9.2e %6.2f %6.2f %6.1f | "
                       "%-7s %14.8g %8.3f",
                       parts[i].name, d, pc->attempts, pc->angle_deg, axis, corpus_op_names[op],
                       x->truth, x->bar,
                       pc->sigma / (pc->va > 0 ? pc->va : 1), pc->za, pc->zb, pc->t_estimate,
                       corpus_verdict_names[x->c.v], x->c.o.volume,
                       isfinite(x->c.o.time_s) ? x->c.o.time_s : x->c.o.wall_s);
                if (occt)
                    printf(" | %-7s %14.8g %8.3f", corpus_verdict_names[x->o.v], x->o.o.volume,
                           isfinite(x->o.o.time_s) ? x->o.o.time_s : x->o.o.wall_s);
                printf("\n");
                fflush(stdout);
            }
        }
    double elapsed = now_s() - t_start;
    if (tty)
        fprintf(stderr, "%100s\r", "");

    printf("\nBy part: verdicts pass / refused / WRONG / crash / timeout; times: medians of the "
           "Boolean's own seconds over the runs both tools passed, and their ratio C/O\n");
    printf("%-34s %4s | %-24s |", "part", "runs", "Colibri pass ref WRNG crsh tmo");
    if (occt)
        printf(" %-24s | %4s %8s %8s %6s", "OCCT    pass ref WRNG crsh tmo", "both", "C s", "O s",
               "C/O");
    else
        printf(" %4s %8s", "pass", "C s");
    printf("\n");
    for (int i = 0; i < np; i++) {
        tally t = tally_of(r, nr, cases, i, -1, occt, sc, so);
        print_tally(parts[i].name, &t, occt);
    }
    printf("\nBy operation:\n");
    for (int op = 0; op < 3; op++) {
        tally t = tally_of(r, nr, cases, -1, op, occt, sc, so);
        print_tally(corpus_op_names[op], &t, occt);
    }
    tally all = tally_of(r, nr, cases, -1, -1, occt, sc, so);
    print_tally("all", &all, occt);

    int unmade = 0;
    for (int k = 0; k < nc; k++)
        unmade += cases[k].error[0] != 0;
    if (unmade) {
        printf("\nCases not made (no run):\n");
        for (int k = 0; k < nc; k++)
            if (cases[k].error[0])
                printf("  %s d%d: %s\n", parts[cases[k].part].name, cases[k].draw,
                       cases[k].error);
    }
    for (int tool = 0; tool < 1 + occt; tool++) {
        printf("\n%s WRONG / crash / timeout:\n", tool ? "OCCT" : "Colibri");
        for (int k = 0; k < nr; k++) {
            const side *s = tool ? &r[k].o : &r[k].c;
            if (s->v >= CORPUS_WRONG)
                printf("  %s d%d %s: %s: %s\n", parts[cases[r[k].case_index].part].name,
                       cases[r[k].case_index].draw, corpus_op_names[r[k].op],
                       corpus_verdict_names[s->v], s->why);
        }
        print_reasons(r, nr, cases, parts, tool);
    }
    double t_est = 0;
    for (int k = 0; k < nc; k++)
        t_est += cases[k].t_estimate;
    printf("\n%d parts, %d cases, %d runs in %.0f s (overlap estimates %.0f s)\n", np, nc, nr,
           elapsed, t_est);

    if (json_path) {
        FILE *f = fopen(json_path, "w");
        if (!f) {
            fprintf(stderr, "bench_parts: cannot write %s\n", json_path);
        } else {
            fprintf(f, "{\"timeout_s\": %g, \"grid\": %d, \"seed\": %llu, \"runs\": [", ro.timeout,
                    co.grid, (unsigned long long)co.seed);
            for (int k = 0; k < nr; k++) {
                const parts_case *pc = cases + r[k].case_index;
                fprintf(f, "%s\n {\"part\": ", k ? "," : "");
                cb_json_string(f, parts[pc->part].name);
                fprintf(f, ", \"draw\": %d, \"angle_deg\": %.17g, \"axis\": [%.17g, %.17g, %.17g], "
                           "\"shift\": [%.17g, %.17g, %.17g], \"op\": \"%s\", \"va\": %.17g, "
                           "\"vb\": %.17g, \"vi\": %.17g, \"sigma\": %.3g, \"truth\": %.17g, "
                           "\"bar\": %.3g, ",
                        pc->draw, pc->angle_deg, pc->axis[0], pc->axis[1], pc->axis[2],
                        pc->shift[0], pc->shift[1], pc->shift[2], corpus_op_names[r[k].op], pc->va,
                        pc->vb, pc->vi, pc->sigma, r[k].truth, r[k].bar);
                corpus_json_side(f, "colibri", &r[k].c);
                if (occt) {
                    fputs(", ", f);
                    corpus_json_side(f, "occt", &r[k].o);
                }
                fputs("}", f);
            }
            fputs("\n]}\n", f);
            fclose(f);
        }
    }

    /* The temporary folder: the tools' files and (without --keep) the moved copies. */
    const char *names[] = {"result.stl", "report.json", "stdout.txt", "stderr.txt",
                           "occt_stdout.txt", "occt_stderr.txt"};
    for (size_t k = 0; k < sizeof names / sizeof *names; k++) {
        snprintf(path, sizeof path, "%s/%s", tmp, names[k]);
        remove(path);
    }
    for (int k = 0; !keep && k < nc; k++)
        remove(cases[k].b_path);
    rmdir(tmp);
    if (only)
        regfree(&re);
    for (int i = 0; i < nm; i++)
        free(models[i]);
    for (int i = 0; i < nf; i++)
        free(files[i]);
    free(models);
    free(files);
    free(ref);
    free(sc);
    free(so);
    free(r);
    free(cases);
    free(parts);
    return 0;
}
