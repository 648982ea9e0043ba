/* ssi_svg.c — colibri ssi --svg: per intersecting face pair, both parameter domains with the
 * curves, isolated points, topology marks and patch boundaries (cli/ssi_svg.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "brep/face.h"
#include "cli/ssi_svg.h"

/* Pixels: the plot square of each panel, the margin around it, title and legend heights. */
#define PLOT 400
#define MARGIN 40
#define TITLE_H 30
#define LEGEND_H 40
#define PANEL_W (PLOT + 2 * MARGIN)

typedef struct {
    int fa, fb;
} face_pair;

static int pair_cmp(const void *x, const void *y)
{
    const face_pair *p = x, *q = y;
    if (p->fa != q->fa)
        return p->fa < q->fa ? -1 : 1;
    return (p->fb > q->fb) - (p->fb < q->fb);
}

/* One face's panel: its uv box and where the plot square sits in the picture. */
typedef struct {
    const cb_topo_body *b;
    int face, side; /* side 0: A, 1: B */
    const cb_topo_surface *s;
    double box[4];  /* {u0, u1, v0, v1} shown */
    double x0, y0;  /* top left corner of the plot square */
    cb_face f;      /* the trimming loops, when have_loops */
    int have_loops;
    char loops_msg[CB_ERROR_MSG_LEN]; /* why the loops are not drawn */
    double shift[2]; /* whole periods moving the loops onto the lift the curves use */
} panel;

static const double *side_uv(const cb_ssi_point *p, int side)
{
    return side ? p->uv_b : p->uv_a;
}

static void box_add(double box[4], const double uv[2])
{
    for (int d = 0; d < 2; d++) {
        box[2 * d] = fmin(box[2 * d], uv[d]);
        box[2 * d + 1] = fmax(box[2 * d + 1], uv[d]);
    }
}

static double px(const panel *P, double u)
{
    return P->x0 + (u - P->box[0]) / (P->box[1] - P->box[0]) * PLOT;
}

static double py(const panel *P, double v)
{
    return P->y0 + PLOT - (v - P->box[2]) / (P->box[3] - P->box[2]) * PLOT;
}

static void xml_text(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else
            fputc(*s, f);
    }
}

/* The box: every output point and mark of the pair on this side, the B-spline's domain, and
 * the trimming loops moved by whole periods next to the curves (pcurves and the SSI may use
 * different lifts of an angle). A flat box (a curve along u = const) is widened by 1. */
static void panel_box(panel *P, const cb_ssi_result_t r, int fa, int fb)
{
    double *box = P->box;
    box[0] = box[2] = HUGE_VAL;
    box[1] = box[3] = -HUGE_VAL;
    for (slong c = 0; c < r->n_curves; c++)
        if (r->curve[c].face_a == fa && r->curve[c].face_b == fb)
            for (slong i = 0; i < r->curve[c].n; i++)
                box_add(box, side_uv(r->curve[c].pt + i, P->side));
    for (slong q = 0; q < r->n_points; q++)
        if (r->point[q].face_a == fa && r->point[q].face_b == fb)
            box_add(box, side_uv(&r->point[q].p, P->side));
    for (slong k = 0; k < r->n_marks; k++)
        if (r->mark[k].face_a == fa && r->mark[k].face_b == fb && r->mark[k].q_side == P->side)
            box_add(box, r->mark[k].uv);
    if (P->have_loops)
        for (int d = 0; d < 2; d++) {
            double per = P->f.inv.period[d];
            double c = 0.5 * (box[2 * d] + box[2 * d + 1]);
            double m = 0.5 * (P->f.uv_box[2 * d] + P->f.uv_box[2 * d + 1]);
            P->shift[d] = per > 0 ? per * round((c - m) / per) : 0;
        }
    if (P->s->kind == CB_SURFACE_NURBS) {
        double dom[4];
        cb_nurbs_surface_domain(P->s->nurbs, dom);
        box_add(box, (double[2]){dom[0], dom[2]});
        box_add(box, (double[2]){dom[1], dom[3]});
    }
    if (P->have_loops) {
        const double *lb = P->f.uv_box;
        box_add(box, (double[2]){lb[0] + P->shift[0], lb[2] + P->shift[1]});
        box_add(box, (double[2]){lb[1] + P->shift[0], lb[3] + P->shift[1]});
    }
    for (int d = 0; d < 2; d++)
        if (!(box[2 * d + 1] > box[2 * d])) {
            box[2 * d] -= 0.5;
            box[2 * d + 1] += 0.5;
        }
}

/* Interior knots of a B-spline surface, one thin grey line each: the Bezier patches' sides,
 * where the SSI's patch pairs meet. */
static void draw_knots(FILE *f, const panel *P)
{
    if (P->s->kind != CB_SURFACE_NURBS)
        return;
    const cb_nurbs_surface_struct *s = P->s->nurbs;
    double dom[4];
    cb_nurbs_surface_domain(s, dom);
    fprintf(f, "<rect class=\"domain\" x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" "
               "fill=\"none\" stroke=\"#999\" stroke-width=\"1\"/>\n",
            px(P, dom[0]), py(P, dom[3]), px(P, dom[1]) - px(P, dom[0]),
            py(P, dom[2]) - py(P, dom[3]));
    for (int d = 0; d < 2; d++) {
        const double *kn = d ? s->knots_v : s->knots_u;
        int deg = d ? s->deg_v : s->deg_u, n = d ? s->n_v : s->n_u;
        for (int i = deg + 1; i < n; i++) {
            if (kn[i] == kn[i - 1] || !(kn[i] > dom[2 * d] && kn[i] < dom[2 * d + 1]))
                continue;
            double x0 = d ? px(P, dom[0]) : px(P, kn[i]), x1 = d ? px(P, dom[1]) : px(P, kn[i]);
            double y0 = d ? py(P, kn[i]) : py(P, dom[2]), y1 = d ? py(P, kn[i]) : py(P, dom[3]);
            fprintf(f, "<line class=\"knot\" x1=\"%.2f\" y1=\"%.2f\" x2=\"%.2f\" y2=\"%.2f\" "
                       "stroke=\"#bbb\" stroke-width=\"0.6\"/>\n",
                    x0, y0, x1, y1);
        }
    }
}

static void draw_loops(FILE *f, const panel *P)
{
    if (!P->have_loops) {
        fputs("<desc>trimming loops not drawn: ", f);
        xml_text(f, P->loops_msg);
        fputs("</desc>\n", f);
        return;
    }
    fputs("<path class=\"loop\" fill=\"none\" stroke=\"#555\" stroke-width=\"1.2\" d=\"", f);
    const double *last = NULL;
    for (int k = 0; k < P->f.n_segs; k++) {
        const cb_face_seg *g = P->f.segs + k;
        if (!last || last[0] != g->p[0] || last[1] != g->p[1])
            fprintf(f, "M%.2f %.2f", px(P, g->p[0] + P->shift[0]), py(P, g->p[1] + P->shift[1]));
        fprintf(f, "L%.2f %.2f", px(P, g->q[0] + P->shift[0]), py(P, g->q[1] + P->shift[1]));
        last = g->q;
    }
    fputs("\"/>\n", f);
}

/* A curve as polylines, a new one wherever consecutive points jump by more than half the box
 * in u or v (a periodic parameter wrapping round): every point is drawn exactly once. */
static void draw_curve(FILE *f, const panel *P, const cb_ssi_curve *cv)
{
    const char *style = cv->tangential
                            ? "stroke=\"#e67e00\" stroke-width=\"2\" stroke-dasharray=\"6 3\""
                            : "stroke=\"#000\" stroke-width=\"1.6\"";
    for (slong i = 0; i < cv->n; i++) {
        const double *uv = side_uv(cv->pt + i, P->side);
        int start = i == 0;
        if (!start) {
            const double *pv = side_uv(cv->pt + i - 1, P->side);
            start = fabs(uv[0] - pv[0]) > 0.5 * (P->box[1] - P->box[0]) ||
                    fabs(uv[1] - pv[1]) > 0.5 * (P->box[3] - P->box[2]);
            if (start)
                fputs("\"/>\n", f);
        }
        if (start)
            fprintf(f, "<polyline class=\"curve\" fill=\"none\" %s points=\"", style);
        fprintf(f, "%s%.2f,%.2f", start ? "" : " ", px(P, uv[0]), py(P, uv[1]));
    }
    if (cv->n > 0)
        fputs("\"/>\n", f);
}

/* A point symbol; cls: write its kind as its class (the legend's samples have none, so that
 * the classes count what the panels show). */
static void draw_mark(FILE *f, const char *kind, double x, double y, int cls)
{
    char c[32] = "";
    if (cls)
        snprintf(c, sizeof c, " class=\"%s\"", kind);
    if (!strcmp(kind, "critical"))
        fprintf(f, "<rect%s x=\"%.2f\" y=\"%.2f\" width=\"8\" height=\"8\" fill=\"#d62728\"/>\n",
                c, x - 4, y - 4);
    else if (!strcmp(kind, "point"))
        fprintf(f, "<circle%s cx=\"%.2f\" cy=\"%.2f\" r=\"4.5\" fill=\"#000\"/>\n", c, x, y);
    else if (!strcmp(kind, "fibre"))
        fprintf(f, "<circle%s cx=\"%.2f\" cy=\"%.2f\" r=\"3\" fill=\"#9467bd\"/>\n", c, x, y);
    else if (!strcmp(kind, "helping"))
        fprintf(f, "<circle%s cx=\"%.2f\" cy=\"%.2f\" r=\"2.5\" fill=\"none\" stroke=\"#1f77b4\" "
                   "stroke-width=\"1.2\"/>\n",
                c, x, y);
    else
        fprintf(f, "<circle%s cx=\"%.2f\" cy=\"%.2f\" r=\"3\" fill=\"#2ca02c\"/>\n", c, x, y);
}

static const char *mark_kind(cb_ctopo_kind k)
{
    switch (k) {
    case CB_CTOPO_CRITICAL:
    case CB_CTOPO_ISOLATED:
        return "critical";
    case CB_CTOPO_FIBRE:
        return "fibre";
    case CB_CTOPO_HELPING:
        return "helping";
    default:
        return "boundary";
    }
}

static void draw_panel(FILE *f, const panel *P, const cb_ssi_result_t r, int fa, int fb)
{
    slong n_marks = 0;
    for (slong k = 0; k < r->n_marks; k++)
        n_marks += r->mark[k].face_a == fa && r->mark[k].face_b == fb &&
                   r->mark[k].q_side == P->side;
    fprintf(f, "<g class=\"panel\" id=\"%c\">\n", P->side ? 'B' : 'A');
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" font-size=\"13\">%c: face %d, %s%s</text>\n", P->x0,
            P->y0 - 8, P->side ? 'B' : 'A', P->face, cb_topo_surface_type_name(P->s),
            n_marks ? " (parameterised side: topology marks)" : "");
    fprintf(f, "<rect x=\"%d\" y=\"%.0f\" width=\"%d\" height=\"%d\" fill=\"none\" "
               "stroke=\"#ddd\"/>\n",
            (int)P->x0, P->y0, PLOT, PLOT);
    fprintf(f, "<text x=\"%.0f\" y=\"%.0f\" font-size=\"11\">u in [%.6g, %.6g], v in [%.6g, "
               "%.6g] (v up)</text>\n",
            P->x0, P->y0 + PLOT + 16, P->box[0], P->box[1], P->box[2], P->box[3]);
    draw_knots(f, P);
    draw_loops(f, P);
    for (slong c = 0; c < r->n_curves; c++)
        if (r->curve[c].face_a == fa && r->curve[c].face_b == fb)
            draw_curve(f, P, r->curve + c);
    for (slong q = 0; q < r->n_points; q++)
        if (r->point[q].face_a == fa && r->point[q].face_b == fb) {
            const double *uv = side_uv(&r->point[q].p, P->side);
            draw_mark(f, "point", px(P, uv[0]), py(P, uv[1]), 1);
        }
    /* Critical points last, on top of the regular marks that share their critical line. */
    for (int pass = 0; pass < 2; pass++)
        for (slong k = 0; k < r->n_marks; k++) {
            const cb_ssi_mark *m = r->mark + k;
            const char *kind = mark_kind(m->kind);
            if (m->face_a == fa && m->face_b == fb && m->q_side == P->side &&
                pass == !strcmp(kind, "critical"))
                draw_mark(f, kind, px(P, m->uv[0]), py(P, m->uv[1]), 1);
        }
    fputs("</g>\n", f);
}

static void draw_legend(FILE *f, double y)
{
    static const char *const label[] = {"curve",       "tangential",  "isolated point",
                                        "critical",    "on crit. line", "helping",
                                        "box side",    "knot line",   "trim loop"};
    static const char *const kind[] = {"critical", "fibre", "helping", "boundary"};
    double x = 12, step = (2.0 * PANEL_W - 24) / 9;
    fputs("<g class=\"legend\" font-size=\"11\">\n", f);
    for (int k = 0; k < 9; k++, x += step) {
        if (k == 0 || k == 1 || k >= 7)
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" %s/>\n", x, y - 4,
                    x + 16, y - 4,
                    k == 0   ? "stroke=\"#000\" stroke-width=\"1.6\""
                    : k == 1 ? "stroke=\"#e67e00\" stroke-width=\"2\" stroke-dasharray=\"6 3\""
                    : k == 7 ? "stroke=\"#bbb\" stroke-width=\"0.6\""
                             : "stroke=\"#555\" stroke-width=\"1.2\"");
        else
            draw_mark(f, k == 2 ? "point" : kind[k - 3], x + 8, y - 4, 0);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\">%s</text>\n", x + 20, y, label[k]);
    }
    fputs("</g>\n", f);
}

/* 0, or the exit status after printing why. */
static int make_dir(const char *dir)
{
    struct stat sb;
    if (!stat(dir, &sb)) {
        if (S_ISDIR(sb.st_mode))
            return 0;
        fprintf(stderr, "colibri ssi: --svg %s exists and is not a directory\n", dir);
        return 2;
    }
    if (mkdir(dir, 0777)) {
        fprintf(stderr, "colibri ssi: --svg: cannot make %s: %s\n", dir, strerror(errno));
        return 2;
    }
    return 0;
}

/* The trimming loops of the panel's face; 1 when memory ran out (a face the loops cannot be
 * made for is drawn without them). */
static int panel_loops(panel *P)
{
    cb_error err;
    cb_error_clear(&err);
    double tol = P->b->tol > 0 ? P->b->tol : 1e-7;
    cb_status st = cb_face_init(&P->f, P->b, P->face, tol, &err);
    P->have_loops = st == CB_OK;
    snprintf(P->loops_msg, sizeof P->loops_msg, "%s", err.msg);
    return st == CB_ERR_NOMEM;
}

static int write_pair(const char *path, const cb_ssi_result_t r, const cb_topo_body *a,
                      const cb_topo_body *b, int fa, int fb)
{
    panel P[2];
    memset(P, 0, sizeof P);
    int nomem = 0;
    for (int k = 0; k < 2; k++) {
        P[k].b = k ? b : a;
        P[k].face = k ? fb : fa;
        P[k].side = k;
        P[k].s = P[k].b->surfaces + P[k].b->faces[P[k].face].surface;
        P[k].x0 = k * PANEL_W + MARGIN;
        P[k].y0 = TITLE_H + MARGIN;
        nomem |= panel_loops(P + k);
        panel_box(P + k, r, fa, fb);
    }
    int rc = 0;
    if (nomem) {
        fprintf(stderr, "colibri ssi: --svg: out of memory for the loops of faces %d, %d\n", fa,
                fb);
        rc = 1;
    }
    FILE *f = rc ? NULL : fopen(path, "w");
    if (!rc && !f) {
        fprintf(stderr, "colibri ssi: cannot write %s: %s\n", path, strerror(errno));
        rc = 2;
    }
    if (f) {
        slong nc = 0, np = 0, nf = 0;
        for (slong c = 0; c < r->n_curves; c++)
            nc += r->curve[c].face_a == fa && r->curve[c].face_b == fb;
        for (slong q = 0; q < r->n_points; q++)
            np += r->point[q].face_a == fa && r->point[q].face_b == fb;
        for (slong k = 0; k < r->n_failed; k++)
            nf += r->failed[k].face_a == fa && r->failed[k].face_b == fb;
        int w = 2 * PANEL_W, h = TITLE_H + PLOT + 2 * MARGIN + LEGEND_H;
        fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                   "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\">\n"
                   "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
                w, h, w, h);
        fprintf(f, "<text x=\"12\" y=\"20\" font-size=\"15\">faces %d of A and %d of B: %ld "
                   "curve%s, %ld isolated point%s",
                fa, fb, (long)nc, nc == 1 ? "" : "s", (long)np, np == 1 ? "" : "s");
        if (nf)
            fprintf(f, "; %ld patch pair%s not certified", (long)nf, nf == 1 ? "" : "s");
        fputs("</text>\n", f);
        draw_panel(f, P, r, fa, fb);
        draw_panel(f, P + 1, r, fa, fb);
        draw_legend(f, h - 14);
        fputs("</svg>\n", f);
        int ok = !ferror(f);
        ok &= fclose(f) == 0;
        if (!ok) {
            fprintf(stderr, "colibri ssi: error writing %s\n", path);
            rc = 2;
        }
    }
    for (int k = 0; k < 2; k++)
        if (P[k].have_loops)
            cb_face_clear(&P[k].f);
    return rc;
}

int cb_cli_ssi_svg(const char *dir, const cb_ssi_result_t r, const cb_topo_body *a,
                   const cb_topo_body *b)
{
    int rc = make_dir(dir);
    if (rc)
        return rc;
    slong n = r->n_curves + r->n_points;
    face_pair *fp = malloc((size_t)(n + 1) * sizeof *fp);
    if (!fp) {
        fprintf(stderr, "colibri ssi: --svg: out of memory\n");
        return 1;
    }
    for (slong c = 0; c < r->n_curves; c++)
        fp[c] = (face_pair){r->curve[c].face_a, r->curve[c].face_b};
    for (slong q = 0; q < r->n_points; q++)
        fp[r->n_curves + q] = (face_pair){r->point[q].face_a, r->point[q].face_b};
    qsort(fp, (size_t)n, sizeof *fp, pair_cmp);
    for (slong k = 0; k < n && !rc; k++) {
        if (k > 0 && !pair_cmp(fp + k, fp + k - 1))
            continue;
        size_t len = strlen(dir) + 64;
        char *path = malloc(len);
        if (!path) {
            fprintf(stderr, "colibri ssi: --svg: out of memory\n");
            rc = 1;
            break;
        }
        snprintf(path, len, "%s/pair_%d_%d.svg", dir, fp[k].fa, fp[k].fb);
        rc = write_pair(path, r, a, b, fp[k].fa, fp[k].fb);
        free(path);
    }
    free(fp);
    return rc;
}
