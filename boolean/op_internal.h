/* op_internal.h — what the stages of cb_bool_run share: the pieces faces are split into and
 * the result under construction. Not installed. */
#ifndef CB_BOOL_OP_INTERNAL_H
#define CB_BOOL_OP_INTERNAL_H

#include "boolean/bool.h"

/* A polyline a face is split along: a stretch of one of its coedges (kind BOUNDARY), a straight
 * join of its loop polygon along a pole line or across a period (JOIN: no edge), or a cut. */
typedef enum { OP_BOUNDARY, OP_JOIN, OP_CUT } op_src_kind;

typedef struct {
    op_src_kind kind;
    int index; /* coedge of the body, or cut */
    int n;
    double *uv; /* 2 n, in the face's window */
} op_src;

/* A stretch of a source polyline between two positions (segment index + fraction), run from
 * pos0 to pos1 when fwd, else back. */
typedef struct {
    int src;
    double pos0, pos1;
    int fwd;
} op_piece;

/* A face piece: a region of the split face kept for the result, as loops of pieces (outer one
 * first), with the face it comes from and whether its normal is turned. */
typedef struct {
    int side; /* 0: from A, 1: from B */
    int face;
    int flip;
    int n_loops;
    int *loop_start; /* n_loops + 1 into pieces */
    op_piece *pieces;
    op_src *srcs; /* the face's sources (owned by the face record, see op_face) */
    int n_srcs;
} op_region;

/* The sources of one face of A or B and the regions kept from it. */
typedef struct {
    int side, face;
    op_src *srcs;
    int n_srcs;
    op_region *regions;
    int n_regions;
} op_face;

void _cb_bool_face_clear(op_face *f);

/* Builds the result body from the kept regions of every face (sources and cuts as the regions
 * refer to them), sewing pieces into edges by their end vertices (welded within weld) and
 * midpoints (two pieces of one curve between the same ends with each other), dropping regions that
 * fold onto themselves, after splitting pieces at the vertices of other pieces that lie inside
 * them (the regions' pieces are rewritten). A and B are the operands, cuts the cuts. tol: the body
 * tolerance. *unmatched counts piece ends that found no partner (the result is then not closed),
 * and where[0 .. n_where) then says where the first of them lies and what it is a piece of. */
cb_status _cb_bool_build(cb_topo_body **out, int *unmatched, char *where, size_t n_where,
                         op_face *faces, int n_faces,
                         const cb_topo_body *A, const cb_topo_body *B, const cb_bool_cuts *cuts,
                         double tol, double weld, cb_error *err);

/* Groups the faces of result b (indexed, every coedge with a pcurve) into shells connected by
 * shared edges, and the shells into solids: each outward shell a solid, with the inward shells
 * (voids) it holds (the smallest outward shell whose box holds the void's). Faces are
 * reordered so that shells are consecutive; b must be indexed again. CB_ERR_NUMERIC for an
 * inward shell inside no outward one, errors of cb_topo_shell_volume, CB_ERR_NOMEM. */
cb_status _cb_bool_split_shells(cb_topo_body *b, cb_error *err);

#endif
