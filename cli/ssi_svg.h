/* ssi_svg.h — pictures of the parameter domains of intersecting faces (colibri ssi --svg). */
#ifndef CB_CLI_SSI_SVG_H
#define CB_CLI_SSI_SVG_H

#include "brep/topo.h"
#include "ssi/ssi.h"

/* Writes dir/pair_<fa>_<fb>.svg for every face pair (fa of a, fb of b) with a curve or an
 * isolated point in r: the parameter domains of both faces side by side, each scaled to fit
 * its square (u across, v up), with the curves (broken where a periodic parameter jumps by
 * more than half the box), isolated points, the knot lines of B-spline surfaces (the Bezier
 * patch boundaries), the trimming loops (brep/face.h; left out for a face cb_face_init
 * refuses) and the topology marks r->mark (run the SSI with opts.keep_marks) on the side that
 * carried them. dir is created when missing (one level). Returns 0, or 2 after printing why on
 * stderr (dir is not a directory or cannot be made, a file cannot be written) or 1 when memory
 * ran out. */
int cb_cli_ssi_svg(const char *dir, const cb_ssi_result_t r, const cb_topo_body *a,
                   const cb_topo_body *b);

#endif
