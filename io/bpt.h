/* bpt.h — Bezier patch text files (.bpt): the first line holds the patch count; each patch is
 * a line "m n" (its bidegree) followed by (m + 1) * (n + 1) lines "x y z", u outer. The
 * classic teapot data uses this format. */
#ifndef CB_IO_BPT_H
#define CB_IO_BPT_H

#include <stddef.h>

#include "brep/nurbs.h"

/* Reads every patch of `path` as a polynomial Bezier surface on [0,1]^2. The array is
 * allocated here and released with cb_nurbs_surface_array_free. A malformed file is rejected
 * with its name and line number in the message. */
cb_status cb_bpt_read(cb_nurbs_surface_struct **patches, int *n_patches, const char *path,
                      cb_error *err);

/* The same from the len bytes at data (no terminator needed); `name` stands for the file in
 * messages. Memory use is bounded by a small multiple of len. */
cb_status cb_bpt_read_buffer(cb_nurbs_surface_struct **patches, int *n_patches,
                             const char *data, size_t len, const char *name, cb_error *err);

#endif
