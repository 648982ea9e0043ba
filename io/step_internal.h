/* step_internal.h — the parts of the STEP reader shared by its files; not a public API.
 *
 * The reader works in three passes over one memory buffer:
 *   step_lex.c    tokenizer and DATA-section parser: every parameter of every entity becomes a
 *                 node of one flat pre-order array (lists and typed values hold their elements
 *                 right after themselves and know their subtree size), every entity a record;
 *   step_table.c  the entity table: records sorted by #id, lookup, typed access to parameters
 *                 with messages that carry file, line, #id and entity name, cycle detection;
 *   step_geom.c, step_bspline.c, step_topo.c, step_units.c  the mapping onto brep/topo.h.
 * Nothing here allocates per token: the node and record arrays grow geometrically, so memory
 * is a fixed multiple of the file size. */
#ifndef CB_IO_STEP_INTERNAL_H
#define CB_IO_STEP_INTERNAL_H

#include <stddef.h>

#include "brep/topo.h"
#include "io/step.h"

/* ---------------------------------------------------------------- parameters --------------- */

typedef enum {
    STEP_INT,     /* 12, -3 */
    STEP_REAL,    /* 1., 0.E+000, -2.5 */
    STEP_STRING,  /* 'text' with '' for a quote; text is the raw span between the quotes */
    STEP_ENUM,    /* .T., .MILLI.; text is the name without the dots */
    STEP_BINARY,  /* "0FF" */
    STEP_REF,     /* #123 */
    STEP_UNSET,   /* $ */
    STEP_DERIVED, /* * */
    STEP_LIST,    /* ( ... ); n elements follow */
    STEP_TYPED    /* NAME( ... ): a typed parameter such as LENGTH_MEASURE(2.E-5); text is the
                     name, n elements follow */
} step_kind;

typedef struct {
    unsigned char kind;
    int line;  /* line of the token in the file, for messages */
    int n;     /* LIST, TYPED: number of direct elements */
    int span;  /* nodes in this subtree, itself included: the next sibling is this + span */
    union {
        double real;   /* REAL, and INT converted */
        long ref;      /* REF */
        struct {
            int off, len; /* STRING, ENUM, BINARY, TYPED: span of the text in the buffer */
        } text;
    } v;
    long ival; /* INT */
} step_node;

/* ---------------------------------------------------------------- entity types ------------- */

/* The entity names the mapping looks at; every other name is STEP_T_OTHER. Kept sorted by
 * name (step_type_lookup searches it). */
#define STEP_TYPES(X)                                                                           \
    X(ADVANCED_FACE)                                                                            \
    X(AXIS1_PLACEMENT)                                                                          \
    X(AXIS2_PLACEMENT_2D)                                                                       \
    X(AXIS2_PLACEMENT_3D)                                                                       \
    X(BEZIER_CURVE)                                                                             \
    X(BEZIER_SURFACE)                                                                           \
    X(BREP_WITH_VOIDS)                                                                          \
    X(B_SPLINE_CURVE)                                                                           \
    X(B_SPLINE_CURVE_WITH_KNOTS)                                                                \
    X(B_SPLINE_SURFACE)                                                                         \
    X(B_SPLINE_SURFACE_WITH_KNOTS)                                                              \
    X(CARTESIAN_POINT)                                                                          \
    X(CIRCLE)                                                                                   \
    X(CLOSED_SHELL)                                                                             \
    X(COMPOSITE_CURVE)                                                                          \
    X(COMPOSITE_CURVE_SEGMENT)                                                                  \
    X(CONICAL_SURFACE)                                                                          \
    X(CONTEXT_DEPENDENT_SHAPE_REPRESENTATION)                                                   \
    X(CONVERSION_BASED_UNIT)                                                                    \
    X(CYLINDRICAL_SURFACE)                                                                      \
    X(DEFINITIONAL_REPRESENTATION)                                                              \
    X(DEGENERATE_TOROIDAL_SURFACE)                                                              \
    X(DIRECTION)                                                                                \
    X(EDGE_CURVE)                                                                               \
    X(EDGE_LOOP)                                                                                \
    X(ELLIPSE)                                                                                  \
    X(FACE_BOUND)                                                                               \
    X(FACE_OUTER_BOUND)                                                                         \
    X(FACE_SURFACE)                                                                             \
    X(GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT)                                                      \
    X(GLOBAL_UNIT_ASSIGNED_CONTEXT)                                                             \
    X(HYPERBOLA)                                                                                \
    X(INTERSECTION_CURVE)                                                                       \
    X(ITEM_DEFINED_TRANSFORMATION)                                                              \
    X(LENGTH_MEASURE_WITH_UNIT)                                                                 \
    X(LENGTH_UNIT)                                                                              \
    X(LINE)                                                                                     \
    X(MANIFOLD_SOLID_BREP)                                                                      \
    X(MAPPED_ITEM)                                                                              \
    X(MEASURE_WITH_UNIT)                                                                        \
    X(NEXT_ASSEMBLY_USAGE_OCCURRENCE)                                                           \
    X(OFFSET_SURFACE)                                                                           \
    X(OPEN_SHELL)                                                                               \
    X(ORIENTED_CLOSED_SHELL)                                                                    \
    X(ORIENTED_EDGE)                                                                            \
    X(PARABOLA)                                                                                 \
    X(PCURVE)                                                                                   \
    X(PLANE)                                                                                    \
    X(PLANE_ANGLE_MEASURE_WITH_UNIT)                                                            \
    X(PLANE_ANGLE_UNIT)                                                                         \
    X(POLYLINE)                                                                                 \
    X(PRODUCT_DEFINITION_SHAPE)                                                                 \
    X(QUASI_UNIFORM_CURVE)                                                                      \
    X(QUASI_UNIFORM_SURFACE)                                                                    \
    X(RATIONAL_B_SPLINE_CURVE)                                                                  \
    X(RATIONAL_B_SPLINE_SURFACE)                                                                \
    X(RECTANGULAR_TRIMMED_SURFACE)                                                              \
    X(REPRESENTATION_MAP)                                                                       \
    X(REPRESENTATION_RELATIONSHIP)                                                              \
    X(REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION)                                          \
    X(SEAM_CURVE)                                                                               \
    X(SHAPE_DEFINITION_REPRESENTATION)                                                          \
    X(SHAPE_REPRESENTATION_RELATIONSHIP)                                                        \
    X(SHELL_BASED_SURFACE_MODEL)                                                                \
    X(SI_UNIT)                                                                                  \
    X(SPHERICAL_SURFACE)                                                                        \
    X(SURFACE_CURVE)                                                                            \
    X(SURFACE_OF_LINEAR_EXTRUSION)                                                              \
    X(SURFACE_OF_REVOLUTION)                                                                    \
    X(TOROIDAL_SURFACE)                                                                         \
    X(TRIMMED_CURVE)                                                                            \
    X(UNCERTAINTY_MEASURE_WITH_UNIT)                                                            \
    X(UNIFORM_CURVE)                                                                            \
    X(UNIFORM_SURFACE)                                                                          \
    X(VECTOR)                                                                                   \
    X(VERTEX_LOOP)                                                                              \
    X(VERTEX_POINT)

#define STEP_TYPE_ENUM(name) STEP_T_##name,
typedef enum { STEP_TYPES(STEP_TYPE_ENUM) STEP_T_COUNT, STEP_T_OTHER = STEP_T_COUNT } step_type;
#undef STEP_TYPE_ENUM

/* Type of the entity name text[0 .. len) (upper case, as STEP writes it). */
step_type step_type_lookup(const char *text, int len);
const char *step_type_name(step_type t);

/* ---------------------------------------------------------------- records ------------------ */

/* One part of an entity instance: the whole of a simple instance NAME(...), or one of the
 * NAME(...) groups of a complex instance (A(...) B(...)). */
typedef struct {
    int type;          /* step_type */
    int name_off, name_len;
    int args;          /* node index of the LIST of its parameters */
} step_part;

typedef struct {
    long id;
    int line;          /* line of '#id' */
    int part0, n_parts;
    int complex;       /* written as (A(...) B(...)) */
} step_rec;

/* Mapping progress of a record, for cycle detection and memoisation. */
enum { STEP_FRESH = 0, STEP_BUSY = 1, STEP_DONE = 2 };

/* The body arrays a memoised record can index. A record reached once as one kind and again as
 * another (a file that names a vertex where an edge belongs) must not reuse the index. */
typedef enum {
    STEP_MEMO_VERTEX = 1,
    STEP_MEMO_CURVE,
    STEP_MEMO_EDGE,
    STEP_MEMO_PCURVE,
    STEP_MEMO_SURFACE
} step_memo_kind;

typedef struct {
    const char *path;  /* name used in messages */
    char *buf;         /* the file, NUL-terminated */
    size_t len;
    step_node *nodes;
    int n_nodes, cap_nodes;
    step_part *parts;
    int n_parts, cap_parts;
    step_rec *recs;    /* sorted by id after step_parse */
    int n_recs, cap_recs;
    /* Mapping state, one slot per record. */
    unsigned char *state;
    int *memo;         /* index of the body object the record became, -1 if none */
    unsigned char *memo_kind; /* which kind of body object memo[k] indexes (step_memo_kind) */
    int depth;         /* nesting of step_enter calls */
    /* Units of the representation being mapped: multiply file angles by angle_rad. */
    double angle_rad;
    double length_mm;
    double uncertainty;
    /* The range of a curve that has no finite exact form without one (PARABOLA, HYPERBOLA):
     * the trims of a TRIMMED_CURVE around it (bound_kind 2: parameters, 1: points), else the
     * vertices of the edge being mapped (bound_kind 1, bound_from_edge); bound_used is set
     * when a curve took its range from the edge, so that it is not shared with other edges. */
    int bound_kind, bound_from_edge, bound_used;
    double bound_pt[2][3], bound_t[2];
    /* The assembly structure, gathered when the first solid is placed (step_units.c). */
    struct step_link *links;
    int n_links, links_ready;
    cb_topo_body *body;
    cb_error *err;     /* where messages go */
} step_file;

/* ---------------------------------------------------------------- step_lex.c --------------- */

/* Tokenizes and parses the whole exchange structure in f->buf (header checked, DATA section
 * parsed into nodes, parts and records); records are then sorted by id and duplicate ids
 * rejected. Errors carry "path:line:". */
cb_status step_parse(step_file *f);

/* ---------------------------------------------------------------- step_table.c ------------- */

void step_file_free(step_file *f);

/* Record with #id, or NULL. */
const step_rec *step_find(const step_file *f, long id);
static inline int step_rec_index(const step_file *f, const step_rec *r)
{
    return (int)(r - f->recs);
}

/* The part of r with type t, or NULL. */
const step_part *step_part_of(const step_file *f, const step_rec *r, step_type t);
/* Type of a simple instance (of the first part of a complex one). */
step_type step_rec_type(const step_file *f, const step_rec *r);
int step_rec_is(const step_file *f, const step_rec *r, step_type t);

/* Sets an error "path:line: #id NAME: message" for record r (line of the record, or of the node
 * when at is given) and returns st. */
cb_status step_fail(const step_file *f, const step_rec *r, const step_node *at, cb_status st,
                    const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* Prefixes an error that a lower layer (cb_nurbs_*_make, cb_frame_make ...) already set. */
cb_status step_fail_prefix(const step_file *f, const step_rec *r, cb_error *err);

/* Parameter list access for a part. step_args checks the count (exactly n) and returns the
 * first element; step_next moves to the next sibling. */
const step_node *step_args(const step_file *f, const step_rec *r, const step_part *p, int n);
static inline const step_node *step_next(const step_node *x) { return x + x->span; }
/* The i-th element of a list (O(i)). */
const step_node *step_elem(const step_node *list, int i);

/* Typed reads of one parameter; each fails with a message naming what was expected and the
 * attribute (what). */
cb_status step_get_real(const step_file *f, const step_rec *r, const step_node *x,
                        const char *what, double *out);
cb_status step_get_int(const step_file *f, const step_rec *r, const step_node *x,
                       const char *what, long lo, long hi, long *out);
cb_status step_get_bool(const step_file *f, const step_rec *r, const step_node *x,
                        const char *what, int *out);
cb_status step_get_list(const step_file *f, const step_rec *r, const step_node *x,
                        const char *what, int min_n, int max_n);
/* A reference that must resolve; the record is returned in *out. */
cb_status step_get_ref(const step_file *f, const step_rec *r, const step_node *x,
                       const char *what, const step_rec **out);
/* 1 when x is an ENUM with the given name. */
int step_is_enum(const step_file *f, const step_node *x, const char *name);

/* Cycle detection around the mapping of a record: step_enter fails on a record already being
 * mapped further up (a cyclic reference) or beyond a fixed nesting depth; step_leave marks it
 * done. */
cb_status step_enter(step_file *f, const step_rec *r);
void step_leave(step_file *f, const step_rec *r);

/* ---------------------------------------------------------------- step_units.c ------------- */

/* Sets f->length_mm, f->angle_rad and f->uncertainty from the context of the representation
 * holding `item` (a solid or shell model); defaults (mm, radian, 1e-6) when there is none. */
cb_status step_units_for(step_file *f, const step_rec *item);
/* The placements of the representation holding `item` in the roots of its assembly: one per
 * path up the assembly's tree, each the composition of the ITEM_DEFINED_TRANSFORMATIONs along
 * it (just the identity for a part file). The tree's links are the representation
 * relationships with a transformation (child rep_1, parent rep_2) and the MAPPED_ITEMs (the
 * mapped representation placed by mapping_origin -> mapping_target into each shape
 * representation holding the item); relationships without a transformation join
 * representations of one shape, either way round. Placements equal to one already found are
 * dropped: an item placed twice at one place is one instance (a MAPPED_ITEM held both by its
 * occurrence's representation and by the master's). *out is a new array of *n (free it). */
cb_status step_placements_for(step_file *f, const step_rec *item, cb_xform **out, int *n);

/* ---------------------------------------------------------------- step_geom.c -------------- */

/* A CARTESIAN_POINT or DIRECTION with dim coordinates (2 or 3; 2 leaves p[2] = 0). */
cb_status step_point(step_file *f, const step_rec *r, int dim, double p[3]);
cb_status step_direction(step_file *f, const step_rec *r, int dim, double d[3]);
/* An AXIS2_PLACEMENT_3D (dim 3) or AXIS2_PLACEMENT_2D in the z = 0 plane (dim 2). */
cb_status step_frame(step_file *f, const step_rec *r, int dim, cb_frame *out);

/* A curve entity (LINE, CIRCLE, ELLIPSE, B-spline, PARABOLA and HYPERBOLA as exact rational
 * quadratics over their range (f->bound_*), TRIMMED_CURVE as its basis curve run in the
 * trimmed curve's sense, or SURFACE_CURVE / SEAM_CURVE / INTERSECTION_CURVE, taken as their
 * 3D curve) as a cb_topo_curve; dim 2 for pcurves, which live in parameter space. out must be
 * initialised; on failure it is left initialised. */
cb_status step_curve(step_file *f, const step_rec *r, int dim, cb_topo_curve *out);
cb_status step_surface(step_file *f, const step_rec *r, cb_topo_surface *out);

/* ---------------------------------------------------------------- step_bspline.c ----------- */

/* B_SPLINE_CURVE_WITH_KNOTS, simple or complex (rational), clamped exactly if the file's
 * knot vector is not; dim 2 for pcurves. */
cb_status step_bspline_curve(step_file *f, const step_rec *r, int dim, cb_nurbs_curve_t out);
cb_status step_bspline_surface(step_file *f, const step_rec *r, cb_nurbs_surface_t out);

/* ---------------------------------------------------------------- step_topo.c -------------- */

/* Maps every solid and shell model of the file into f->body, each in its assembly placement. */
cb_status step_map_body(step_file *f);

/* ---------------------------------------------------------------- step_tol.c --------------- */

/* Raises edge tolerances to the edges' measured deviations up to max_rel times the edge-box
 * diagonal (step.h); needs the incidence index and the pcurves. Fills all of *stats. Fails
 * only with CB_ERR_NOMEM. */
cb_status step_fit_edge_tols(cb_topo_body *b, double max_rel, cb_step_stats *stats,
                             cb_error *err);

#endif
