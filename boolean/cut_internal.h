/* cut_internal.h — what boolean/cut.c and boolean/imprint.c share: curve points with their
 * parameters on both faces, runs of them, and turning a run into cuts. */
#ifndef CB_BOOLEAN_CUT_INTERNAL_H
#define CB_BOOLEAN_CUT_INTERNAL_H

#include "boolean/bool.h"

/* One curve point with its parameters on both faces (side 0: A's face, 1: B's). */
typedef struct {
    double xyz[3];
    double uv[2][2];
} cut_pt;

typedef struct {
    int n, cap;
    cut_pt *p;
} cut_run;

/* Appends p; -1 when out of memory. */
int _cb_cut_run_push(cut_run *r, const cut_pt *p);

/* The two faces of a cut with their periodic windows (bool.h: cb_bool_cut), and the
 * tolerance. */
typedef struct {
    const cb_face *f[2];
    double lo[2][2], P[2][2]; /* per side and direction; P 0 where not periodic */
    double hi[2][2], band[2][2]; /* of a face spanning a whole period with a seam: the upper
                                    copy of the seam (lo the lower) and twice the mismatch of
                                    the two copies (see inside_both in cut.c); band -1
                                    otherwise */
    double min_len;
} cut_ctx;

void _cb_cut_ctx_init(cut_ctx *cx, const cb_face *fa, const cb_face *fb, double tol);

/* Wraps the periodic parameters of run r into the faces' windows, splits it where a lift
 * jumps, and appends the pieces to out as cuts of c's faces (c->face_a, c->face_b; c's
 * tangential flag copied; curve: the index recorded). An open run shorter than the tolerance
 * is dropped. */
cb_status _cb_cut_split_emit(cb_bool_cuts *out, cut_run *r, int closed, const cut_ctx *cx,
                             const cb_ssi_curve *c, int curve, cb_error *err);

/* Whether cut c runs along the boundary of its face F on side `side`: every point, and the
 * middle of every segment longer than the weld distance (CB_BOOL_WELD tol), ON the boundary
 * within CB_BOOL_SNAP tol (cb_face_classify_uv: plus the edge's distance from the surface).
 * The face's split drops such a cut (boolean/op.c). */
int _cb_cut_along_boundary(const cb_bool_cut *c, int side, const cb_face *F, double tol);

/* The imprints of coincident faces (boolean/imprint.c): for every record of r->coincident,
 * the boundary edges of each face where they lie inside the other face, appended to out as
 * cuts of the pair (curve index -1). */
cb_status _cb_cuts_imprint(cb_bool_cuts *out, const cb_ssi_result_struct *r,
                           const cb_bool_solid *A, const cb_bool_solid *B, double tol,
                           cb_error *err);

/* Prepares A and B for classification (S, cb_bool_solid_new; the two side by side on up to
 * `threads` threads, 0: all) and makes the cuts of r between them (cb_bool_cuts_make). The
 * caller frees S[0], S[1] (NULL when not made) and clears cuts, whatever the status. */
cb_status _cb_bool_solids_cuts(cb_bool_solid *S[2], cb_bool_cuts *cuts,
                               const cb_ssi_result_struct *r, const cb_topo_body *A,
                               const cb_topo_body *B, double tol, int threads, cb_error *err);

#endif
