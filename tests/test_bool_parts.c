/* test_bool_parts.c — Booleans of real CAD parts (../shared) against copies moved by rigid
 * motions that bench_parts' generator drew (seed 1; the draws' angles, axes and shifts copied
 * from its JSON output), scored against V(A), V(B) by mass integration and V(A n B) by the
 * overlap estimate of that run (cb_model_overlap_estimate, 600 x 600 lines, with its sigma):
 * no Boolean code in the truth. The bar is bench_parts': 4 sigma + 1e-6 |truth| + 1e-9 (V(A) +
 * V(B)). Each result must also be valid, mesh closed (cb_tess_body, cb_mesh_check; the
 * operations a case lists in no_mesh are known not to) and its three volumes satisfy
 * inclusion-exclusion to 2e-6 (ujoint_fork draw 0 is 8e-7 off: the intersection's pieces lie
 * within the parts' tolerance, 1.8e-4 on faces of area 4.5e4, of the exact ones). The draws
 * are the real-parts class of issue 22 that pass; the comments by the cases say what each
 * one exercises. Skipped (exit status 77) where ../shared is missing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "boolean/bool.h"
#include "brep/mass.h"
#include "brep/mesh_check.h"
#include "brep/tess.h"
#include "io/step.h"
#include "io/step_write.h"
#include "ssi/ssi.h"
#include "check.h"

static const double PI = 3.14159265358979323846;

typedef struct {
    const char *path; /* under ../shared */
    int draw;
    double angle_deg, axis[3], shift[3];
    double vi, sigma; /* the overlap estimate of V(A n B) and its standard deviation */
    int no_mesh;      /* operations (bit k: ops[k] of run_case) whose result's mesh is not
                         checked: known to fail (bench/README.md lists them), the B-rep still
                         checked; 0 for the others */
    int skip;         /* operations not run (bit k as above): known to be refused
                         (bench/README.md); inclusion-exclusion is then not checked */
} parts_case;

static const parts_case CASES[] = {
    {"models/ujoint_fork.step", 0, 30.576083296203418,
     {-0.27211509281185203, 0.96179927251897535, 0.029925501599254601},
     {25.498955597526518, 8.9148029240112656, 30.634394383433754}, 4974.8132437652712, 1.83, 0, 0},
    {"models/ujoint_fork.step", 1, 59.568266183345365,
     {-0.84236743098377764, 0.16440931897304484, 0.51321212675911143},
     {9.9516747759695559, 5.2977124118393224, -9.972589903988208}, 20508.020447523661, 4.82, 0, 0},
    {"models/ujoint_fork.step", 2, 52.800408255541207,
     {0.62182171857205604, -0.71284971582884793, 0.32431933792918599},
     {-2.2926651532806108, 22.19238216392527, -0.07293354911127127}, 12403.692005598446, 4.15, 0, 0},
    /* a cone band 0.0144 wide crossed by a cylinder: the clipping's sample between two
     * outside ones was called slid off the chord (the chord runs round the cylinder, its
     * extent along the axis next to nothing) and the piece across the band was dropped from a
     * certified pair (ssi/clip.c mid_sample; 11 edges unsewn) */
    {"corpus/step/OCC2368.stp", 0, 29.47190716036811,
     {0.8068445164274971, -0.1128827286597875, -0.5798787941296},
     {-15.880481888939928, 56.25369611953998, -11.620395912651759}, 98461.37196170723, 21.1, 0, 0},
    {"corpus/step/OCC2368.stp", 1, 8.2143832470671434,
     {0.45614142115039424, 0.58531217032409555, -0.67033175904278597},
     {19.910091179598876, -24.433506812979939, -31.288642882010762}, 88864.159544235052, 17, 0, 0},
    {"corpus/step/OCC2368.stp", 2, 49.011519398551371,
     {-0.80611646160686445, -0.59155289714979831, 0.015537702536373798},
     {34.866040107769059, -45.797947096572159, 19.828819976402293}, 72411.145152039884, 16.8, 0, 0},
    /* trj5 turned 7 degrees: curves turning corners on the creases of its extruded-polyline
     * B-spline walls (kink_split), boundary pieces ending at the creases (their edges'
     * pcurves kept), edges inverted next to a crease (the inverter's restart) */
    {"models/trj5_k1-al-214.stp", 1, 7.0279311799323043,
     {0.65339800319336172, 0.73693772093539778, 0.17318731156025746},
     {0.070272403717423673, 1.492553101566471, 0.64939584095908687}, 0.29307107223056023,
     0.00049, 0, 0},
    {"corpus/step/trj9_io1-sy-214.stp", 0, 50.716860759438177,
     {-0.95865219685044434, 0.23529752824489181, -0.16006573235911917},
     {26.943761607248486, -6.7500554075926402, 12.523609391115301}, 7597.1699902479359, 2.31, 0, 0},
    {"corpus/step/trj9_io1-sy-214.stp", 1, 14.942403502997619,
     {0.6198902097729132, 0.19367342983769489, 0.76041221084527388},
     {16.856472609938564, -20.990362068604909, -33.173079771806208}, 3612.8511020217547, 1.7, 0, 0},
    {"corpus/step/trj9_io1-sy-214.stp", 2, 33.425959463184668,
     {-0.15636709049764819, 0.046724135386699166, -0.98659322325954879},
     {-4.8188636109080614, -11.879345365078935, 21.17584821169822}, 11111.045668505898, 3.26, 0, 0},
    /* B-spline half cylinders of rounded conic weights: the algebraic route's clipping kept a
     * traced piece only where the Dixon inversion found a preimage in the patch, and it found
     * none at all on them (ssi/clip.c keep_piece; 111 edges left unsewn) */
    {"corpus/step/trj2_io1-ca-214.stp", 0, 36.905694138528645,
     {-0.4963696092931887, -0.23447426883943023, 0.8358462946154285},
     {-7.866084733011483, 10.902088143119492, 22.551197767804222}, 13345.76741062293, 3.16, 0, 0},
    /* draw 1: in the union and difference, chords of a curved edge of a planar face, sampled
     * at the default chordal tolerance, cut past a vertex of the cut 0.09 inside the curve:
     * the face's edges are sampled more finely there (brep/tess_body.c) */
    {"corpus/step/trj2_io1-ca-214.stp", 1, 44.824757299029635,
     {-0.08270330469190759, 0.6707244486511097, 0.737081323447218},
     {13.843804932748059, -32.854365100760546, -23.175369807425596}, 10443.04860576789, 3.61,
     0, 0},
    /* draw 2: an edge of the copy passing 0.006 from an edge of a planar face of it (35
     * tolerances), the face's curve ending there off its boundary, the piece of curve between
     * not given: the end moved onto the boundary (boolean/cut.c attach_loose_ends) */
    {"corpus/step/trj2_io1-ca-214.stp", 2, 43.71071435137171,
     {0.5632665988367054, 0.5721805100773375, -0.5961041876405231},
     {22.311827341829794, 3.5308602814942804, 38.50595809431225}, 10918.075533705232, 3.22, 0, 0},
    /* a cut edge running most of the way round a closed B-spline face: its pcurve's way round
     * judged at the edge's tolerance in the mass integration */
    {"corpus/step/trj10_ch1-id-chs.stp", 2, 33.9213379029793,
     {-0.02383298506630569, -0.8617711418472894, 0.5067370993938063},
     {1.5273299131335072, -3.082801158217376, -2.760148266083595}, 213.62522143104988, 0.00948, 0, 0},
    /* a band of revolution with a slot half a turn from its seam: the slot's loop lifted to
     * the band's range (brep/face.c) */
    {"corpus/step/trj6_k1-ec-214.stp", 1, 57.393675131325416,
     {-0.21524722256901632, -0.6466416905412841, 0.7317944774526756},
     {-0.5004220242724419, 0.051289050668659145, 0.33510474556649533}, 0.015179121442459677,
     4.62e-05, 0, 0},
    /* draw 2, and trj10 draw 0 below: faces meeting at a thin wedge, whose triangles cut
     * across a bend of their common edges by the same segment (the mesh split there,
     * brep/tess_body.c) */
    {"corpus/step/trj6_k1-ec-214.stp", 2, 42.2338781232143,
     {0.4781939083988315, 0.7699821608901041, -0.4224429640569905},
     {-0.3747218080931256, -0.45308732098721344, -1.0324196759978346}, 0.012168694500691607,
     2.04e-05, 0, 0},
    /* draw 0, the union: cut ends 7.2e-5 (12 tol) off a face's boundary in (u, v), where the
     * loop polygon strays from the pcurves by up to 3.2e-4 and the arrangement follows the
     * pcurves: moved onto the pcurve (boolean/cut.c attach_loose_ends). The intersection's
     * mesh crosses itself and the difference is not valid (a face turned against its
     * neighbour across an edge 0.0007 long): not run */
    {"corpus/step/trj6_k1-ec-214.stp", 0, 34.55451796226792,
     {-0.1626333778622413, -0.9836260158455326, 0.07765465444493094},
     {0.04727228733701714, 0.11091452978182566, 0.6303925946086909}, 0.06321539830044816,
     2.28e-05, 0, 6},
    /* an edge of B passing 0.0017 from a seam of A's closed B-spline face, under the weld
     * distance: the node where the curve leaves the face welded onto the seam in 3D but left
     * 0.0008 short of it in (u, v) (boolean/cut.c snap_ends); the mesh of the difference
     * as trj6 draw 2's */
    {"corpus/step/trj10_ch1-id-chs.stp", 0, 15.563289140790761,
     {-0.020288683766995847, -0.6541669542146539, -0.7560780153691324},
     {0.6384427238371619, 0.33561892461507925, -1.801057376620718}, 390.1732074194523, 0.0122,
     0, 0},
    /* linkrods (bicubic and degree-(6, 10) sweeps) turned 39 degrees, the union: edges whose
     * tolerance the reader raised to 4.3e-4 where the file's faces stray from them (64
     * tolerances), so the two faces of such an edge put the copy's crossing of it up to 1e-3
     * apart, beyond the weld distance: ends welded within the edges' tolerance and attached
     * to the boundary point nearest in space (boolean/cut.c snap_ends, attach_loose_ends;
     * 10 edges unsewn before). The other operations as the union: not run, for time */
    {"models/linkrods.step", 1, 38.77810412185257,
     {-0.539084248294737, -0.5322090138763409, -0.6527953268745658},
     {1.3109283240843685, 0.2801649088883169, -0.9756202035209104}, 0.2663303307966247,
     0.000227, 0, 6},
    /* linkrods turned 20 degrees, the intersection: A's cylinder face 10 against B's sweep face
     * 25, whose Bezier patch nearly folds (|S_t| 0.002, S_s and S_t 4-8 degrees apart, normal
     * coefficients 169 degrees apart over sub-patches 1e-5 wide) in two regions 4 and 8 tol
     * across that no rule resolves; they lie outside face 25's trimming loops, so the pair is
     * not refused (ssi/ssi_body.c drop_outside; refused before). The union as the
     * intersection, the difference not valid (bench/README.md): not run, for time */
    {"models/linkrods.step", 2, 20.195740216581182,
     {0.2066954085836244, -0.1429264231089532, 0.9679096267977342},
     {-0.5357300180388233, 0.4351590653223639, -0.08374476761181025}, 0.4609720428451012,
     0.000204, 0, 5},
};

static double volume(const cb_topo_body *b, const char *what)
{
    cb_mass_props m;
    cb_error err;
    cb_status st = cb_mass_body(&m, b, 1e-9, NULL, &err);
    CHECK(st == CB_OK, "%s: mass: %s", what, err.msg);
    return st ? NAN : m.volume;
}

/* The part moved as bench_parts moves it: turned about its centroid, shifted, written by the
 * STEP writer and read back. */
static cb_topo_body *moved_copy(const char *path, const parts_case *c, const double centroid[3],
                                const char *name)
{
    cb_topo_body *b = NULL;
    cb_error err;
    if (cb_step_read(&b, path, &err)) {
        CHECK(0, "%s: %s", path, err.msg);
        return NULL;
    }
    cb_xform r, t, x;
    cb_xform_rotation(&r, centroid, c->axis, c->angle_deg * PI / 180);
    cb_xform_translation(&t, c->shift);
    cb_xform_compose(&x, &t, &r);
    cb_topo_body_transform(b, &x);
    char tmp[1024];
    const char *dir = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    snprintf(tmp, sizeof tmp, "%s/colibri_bool_parts_%d.step", dir, (int)getpid());
    cb_status st = cb_step_write(b, tmp, name, &err);
    cb_topo_body_free(b);
    b = NULL;
    if (!st)
        st = cb_step_read(&b, tmp, &err);
    remove(tmp);
    CHECK(st == CB_OK, "%s draw %d: moved copy: %s", name, c->draw, err.msg);
    return st ? NULL : b;
}

static void run_case(const char *shared, const parts_case *c)
{
    const char *only = getenv("PARTS_ONLY"); /* a debugging aid: one part's cases */
    if (only && !strstr(c->path, only))
        return;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", shared, c->path);
    const char *name = strrchr(c->path, '/') + 1;
    cb_topo_body *A = NULL, *B = NULL;
    cb_error err;
    if (cb_step_read(&A, path, &err)) {
        CHECK(0, "%s: %s", path, err.msg);
        return;
    }
    cb_mass_props m;
    if (cb_mass_body(&m, A, 1e-9, NULL, &err)) {
        CHECK(0, "%s: mass: %s", name, err.msg);
        cb_topo_body_free(A);
        return;
    }
    B = moved_copy(path, c, m.centroid, name);
    double va = m.volume, vb = B ? volume(B, name) : NAN, got[3] = {NAN, NAN, NAN};
    const cb_bool_op ops[3] = {CB_BOOL_UNION, CB_BOOL_INTERSECTION, CB_BOOL_DIFFERENCE};
    const double truth[3] = {va + vb - c->vi, c->vi, va - c->vi};
    for (int k = 0; k < 3 && B; k++) {
        if (c->skip >> k & 1)
            continue;
        cb_topo_body *R = NULL;
        cb_status st = cb_bool_run(&R, NULL, ops[k], A, B, NULL, NULL, &err);
        CHECK(st == CB_OK, "%s draw %d %s: %s", name, c->draw, cb_bool_op_name(ops[k]), err.msg);
        if (!st) {
            cb_topo_report r;
            cb_topo_report_init(&r);
            cb_status vs = cb_topo_validate(&r, R, 0, 9, &err);
            CHECK(vs == CB_OK && r.n == 0, "%s draw %d %s: not valid: %s", name, c->draw,
                  cb_bool_op_name(ops[k]), vs ? err.msg : r.n ? r.items[0] : "");
            cb_topo_report_clear(&r);
            got[k] = volume(R, name);
            if (!(c->no_mesh >> k & 1)) {
                /* the result meshes closed, as colibri bool requires of it */
                cb_mesh_t mesh;
                cb_mesh_init(mesh);
                cb_mesh_check_report mr;
                cb_status ms = cb_tess_body(mesh, R, NULL, NULL, &err);
                if (!ms)
                    ms = cb_mesh_check(&mr, mesh, &err);
                CHECK(!ms && mr.closed, "%s draw %d %s: mesh: %s", name, c->draw,
                      cb_bool_op_name(ops[k]), ms ? err.msg : "not closed");
                cb_mesh_clear(mesh);
            }
            double bar = 4 * c->sigma + 1e-6 * fabs(truth[k]) + 1e-9 * (va + vb);
            CHECK(fabs(got[k] - truth[k]) <= bar,
                  "%s draw %d %s: volume %.9g, truth %.9g (bar %.3g)", name, c->draw,
                  cb_bool_op_name(ops[k]), got[k], truth[k], bar);
        }
        cb_topo_body_free(R);
    }
    if (B && !c->skip)
        CHECK(fabs(got[0] + got[1] - va - vb) <= 2e-6 * (va + vb) &&
                  fabs(got[2] + got[1] - va) <= 2e-6 * va,
              "%s draw %d: inclusion-exclusion: union %.9g + intersection %.9g vs %.9g, "
              "difference %.9g + intersection vs %.9g",
              name, c->draw, got[0], got[1], va + vb, got[2], va);
    printf("%-24s draw %d: union %.6f intersection %.6f difference %.6f\n", name, c->draw,
           got[0], got[1], got[2]);
    cb_topo_body_free(A);
    cb_topo_body_free(B);
}

/* The SSI of a band of a cone written as one span of a cubic B-spline reaching the apex (trj5's
 * face 28: x from 8.89 to 9.144 cm of a cone round the x axis whose apex is at x = 8.128, the
 * circles polynomial, 5.9e-4 out of round) against its copy turned 30 degrees about the axis:
 * the two bands cross along lines where their out-of-roundness crosses, and the surfaces also
 * meet at the apex, a point of both that subdivision cannot separate. The SSI takes the part
 * of each surface its face reaches (ssi/ssi_body.c restrict_nurbs): no patch pair refused (18
 * of 25, over the sub-pair budget at the apex, when the span was kept whole). The tolerance is
 * the Boolean's default, 1e-6 of the part's size. */
static void test_cone_band(const char *shared)
{
    const char *only = getenv("PARTS_ONLY");
    if (only && !strstr("models/trj5_k1-al-214.stp", only))
        return;
    char path[1024];
    snprintf(path, sizeof path, "%s/models/trj5_k1-al-214.stp", shared);
    cb_topo_body *b[2] = {NULL, NULL};
    cb_error err;
    for (int k = 0; k < 2; k++)
        if (cb_step_read(b + k, path, &err)) {
            CHECK(0, "%s: %s", path, err.msg);
            cb_topo_body_free(b[0]);
            return;
        }
    cb_aabb box;
    cb_topo_body_edge_box(&box, b[0]);
    const double size = cb_vec3_dist(box.lo, box.hi), o[3] = {0, 0, 0}, x[3] = {1, 0, 0};
    const int face = 28;
    const cb_topo_surface *s = b[0]->surfaces + b[0]->faces[face].surface;
    int ok = b[0]->n_faces == 39 && s->kind == CB_SURFACE_NURBS && s->nurbs->n_u == 11 &&
             s->nurbs->n_v == 4;
    CHECK(ok, "trj5: face %d is not the cone band", face);
    for (int k = 0; ok && k < 2; k++) {
        /* the face alone: the SSI reads only the faces (their loops, pcurves and edges) */
        b[k]->faces[0] = b[k]->faces[face];
        b[k]->n_faces = 1;
    }
    cb_xform turn;
    cb_xform_rotation(&turn, o, x, 30 * PI / 180);
    cb_topo_body_transform(b[1], &turn);
    cb_ssi_opts opts;
    cb_ssi_opts_default(&opts);
    opts.tol = 1e-6 * size;
    opts.threads = 1;
    cb_ssi_result_t r;
    cb_ssi_result_init(r);
    if (ok) {
        cb_status st = cb_ssi_bodies(r, b[0], b[1], &opts, &err);
        CHECK(st == CB_OK && r->n_failed == 0 && r->n_curves > 0,
              "trj5 cone band against its turned copy: %s, %ld refused, %ld curves",
              st ? err.msg : "ok", (long)r->n_failed, (long)r->n_curves);
        printf("trj5 cone band: %ld curves, patch pairs %ld (%ld certified, %ld within "
               "tolerance), %ld sub-pairs\n",
               (long)r->n_curves, (long)r->pairs_total, (long)r->pairs_certified,
               (long)r->pairs_within_tolerance, (long)r->subpairs);
    }
    cb_ssi_result_clear(r);
    cb_topo_body_free(b[0]);
    cb_topo_body_free(b[1]);
}

int main(void)
{
    const char *shared = getenv("COLIBRI_SHARED") ? getenv("COLIBRI_SHARED") : "../shared";
    char probe[1024];
    snprintf(probe, sizeof probe, "%s/models/ujoint_fork.step", shared);
    if (access(probe, R_OK)) {
        printf("test_bool_parts: %s not found, skipped\n", probe);
        return 77;
    }
    test_cone_band(shared);
    for (size_t k = 0; k < sizeof CASES / sizeof CASES[0]; k++)
        run_case(shared, CASES + k);
    return check_report("test_bool_parts");
}
