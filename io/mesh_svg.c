/* mesh_svg.c — a shaded picture of a triangle mesh as SVG (cb_mesh_write_svg in io/mesh.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brep/geom.h"
#include "io/mesh.h"

typedef struct {
    double depth;
    int tri;
    int shade;
} drawn;

static int by_depth(const void *a, const void *b)
{
    const drawn *x = a, *y = b;
    if (x->depth != y->depth)
        return x->depth < y->depth ? -1 : 1;
    return (x->tri > y->tri) - (x->tri < y->tri);
}

static void normalise(double v[3])
{
    double n = sqrt(cb_vec3_dot(v, v));
    for (int i = 0; i < 3; i++)
        v[i] /= n;
}

cb_status cb_mesh_write_svg(const char *path, const cb_mesh_t mesh, const char *title, int width,
                            cb_error *err)
{
    const cb_mesh_struct *m = mesh;
    if (m->n_triangles <= 0)
        return cb_error_set(err, CB_ERR_INVALID, "%s: no triangle to draw", path);
    if (width < 16 || width > 20000)
        return cb_error_set(err, CB_ERR_INVALID, "%s: picture width %d not in [16, 20000]", path,
                            width);
    /* Eye towards the viewer, screen right and up: an orthonormal frame with z up on screen. */
    double eye[3] = {1, -1.5, 1}, up[3] = {0, 0, 1}, right[3], upv[3];
    normalise(eye);
    cb_vec3_cross(right, up, eye);
    normalise(right);
    cb_vec3_cross(upv, eye, right);
    double light[3] = {1.3, -1.2, 1.6};
    normalise(light);
    drawn *d = malloc((size_t)m->n_triangles * sizeof *d);
    if (!d)
        return cb_error_set(err, CB_ERR_NOMEM, "%s: out of memory", path);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    int n = 0;
    for (int t = 0; t < m->n_triangles; t++) {
        const double *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = m->xyz + 3 * m->tri[3 * t + k];
        double e1[3], e2[3], nrm[3];
        for (int i = 0; i < 3; i++) {
            e1[i] = p[1][i] - p[0][i];
            e2[i] = p[2][i] - p[0][i];
        }
        cb_vec3_cross(nrm, e1, e2);
        double len = sqrt(cb_vec3_dot(nrm, nrm));
        for (int k = 0; k < 3; k++) {
            double x = cb_vec3_dot(p[k], right), y = cb_vec3_dot(p[k], upv);
            lo[0] = fmin(lo[0], x);
            hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y);
            hi[1] = fmax(hi[1], y);
        }
        if (!(len > 0) || cb_vec3_dot(nrm, eye) <= 0)
            continue;
        double c[3] = {(p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3,
                       (p[0][2] + p[1][2] + p[2][2]) / 3};
        double lambert = fmax(0, cb_vec3_dot(nrm, light) / len);
        d[n].depth = cb_vec3_dot(c, eye);
        d[n].tri = t;
        d[n].shade = (int)lround(70 + 185 * lambert);
        n++;
    }
    qsort(d, (size_t)n, sizeof *d, by_depth);
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (!(span > 0) || !isfinite(span)) {
        free(d);
        return cb_error_set(err, CB_ERR_INVALID, "%s: the mesh has no extent to draw", path);
    }
    double s = (width - 20) / span;
    int w = (int)ceil((hi[0] - lo[0]) * s) + 20, h = (int)ceil((hi[1] - lo[1]) * s) + 20;
    int top = title ? 24 : 0;
    FILE *f = fopen(path, "w");
    if (!f) {
        free(d);
        return cb_error_set(err, CB_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    }
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
            "viewBox=\"0 0 %d %d\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            w, h + top, w, h + top);
    if (title) {
        fputs("<text x=\"10\" y=\"18\" font-family=\"sans-serif\" font-size=\"14\">", f);
        for (const char *c = title; *c; c++) {
            if (*c == '<')
                fputs("&lt;", f);
            else if (*c == '&')
                fputs("&amp;", f);
            else
                fputc(*c, f);
        }
        fputs("</text>\n", f);
    }
    fputs("<g stroke-width=\"0.4\" stroke-linejoin=\"round\">\n", f);
    for (int k = 0; k < n; k++) {
        const int *t = m->tri + 3 * d[k].tri;
        int g = d[k].shade, b = g + (255 - g) / 3;
        fprintf(f, "<path fill=\"#%02x%02x%02x\" stroke=\"#%02x%02x%02x\" d=\"", g * 3 / 4, g * 7 / 8,
                b, g * 3 / 4, g * 7 / 8, b);
        for (int j = 0; j < 3; j++) {
            const double *p = m->xyz + 3 * t[j];
            fprintf(f, "%c%.1f %.1f", j ? 'L' : 'M', 10 + (cb_vec3_dot(p, right) - lo[0]) * s,
                    top + 10 + (hi[1] - cb_vec3_dot(p, upv)) * s);
        }
        fputs("Z\"/>\n", f);
    }
    fputs("</g>\n</svg>\n", f);
    free(d);
    if (fclose(f))
        return cb_error_set(err, CB_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    return CB_OK;
}
