/* mesh.h — triangle mesh files: STL, OBJ, PLY and OFF. Written through OpenMesh; STL and OBJ
 * read through OpenMesh, OFF and PLY by Colibri's own readers (io/mesh_file.c), as OpenMesh
 * 9.0's readers of these two formats read on past a file's end or a bad number with stale
 * values, and loop for ever on a PLY header cut short.
 *
 * The format is chosen by the file extension (case-insensitive): .stl, .obj, .ply, .off.
 * Vertices are shared in every format that can share them (all but STL, which stores three
 * points per triangle; reading an STL file shares exactly equal points again).
 *
 * Precision: OpenMesh 9.0 hands coordinates to its writers and from its readers as 32-bit
 * floats in every one of these formats (measured: a double written to OBJ, OFF or PLY comes
 * back rounded to the nearest float; the PLY header says "float"), so a file holds each
 * coordinate to about 7 significant digits (relative 6e-8) whatever the format allows. Text
 * is written with 17 digits so that the float itself is exact in the file. For binary STL,
 * float is the format's own definition. Colibri's readers keep what the file holds: OFF text
 * as doubles, binary OFF as floats, PLY in each property's declared type.
 *
 * OpenMesh's readers and writers and its log streams are process-global: do not call these
 * functions from several threads at once. */
#ifndef CB_IO_MESH_H
#define CB_IO_MESH_H

#include "brep/mesh.h"
#include "brep/status.h"

typedef enum { CB_MESH_STL, CB_MESH_OBJ, CB_MESH_PLY, CB_MESH_OFF } cb_mesh_format;

typedef struct {
    int stl_ascii; /* write STL as text instead of binary */
} cb_mesh_write_options;

/* The format named by path's extension; CB_ERR_UNSUPPORTED, listing the known extensions,
 * for any other. */
cb_status cb_mesh_format_of_path(cb_mesh_format *fmt, const char *path, cb_error *err);

/* Writes mesh to path in the format of its extension, with the defaults above when opt is
 * NULL. CB_ERR_UNSUPPORTED for an unknown extension, CB_ERR_IO when the file cannot be
 * written (with the system's reason when it cannot be created). */
cb_status cb_mesh_write(const char *path, const cb_mesh_t mesh, const cb_mesh_write_options *opt,
                        cb_error *err);

/* Writes a picture of the mesh as an SVG file: its triangles seen from the direction
 * (1, -1.5, 1) (orthographic, z up), drawn back to front, each shaded by the angle of its normal
 * to a fixed light, triangles facing away from the viewer left out (the mesh is taken to be a
 * closed outward-oriented surface); title is written above the picture (NULL: none). The
 * picture is width x width pixels in its largest direction, width in [16, 20000]. CB_ERR_INVALID
 * for an empty mesh or a bad width, CB_ERR_IO when the file cannot be written, CB_ERR_NOMEM. */
cb_status cb_mesh_write_svg(const char *path, const cb_mesh_t mesh, const char *title, int width,
                            cb_error *err);

/* Replaces the contents of mesh with the triangles of the file at path (format by extension);
 * vertices keep the file's order and sharing. CB_ERR_IO when the file cannot be opened or is
 * not a regular file ("is a directory", "not a regular file"); CB_ERR_PARSE when it cannot be
 * read, or it holds no triangle, or a face is not a valid triangle (the message names the
 * face); CB_ERR_UNSUPPORTED for faces of more than three vertices, which this triangle mesh
 * type does not hold. mesh is empty on failure.
 * OFF and PLY files are read whole and checked as they are read: every count the header
 * announces must be met (no fewer items, nothing after them), every coordinate must be a
 * finite decimal number, every index a whole number naming a vertex; each failure is
 * CB_ERR_PARSE naming the file and line (the byte offset in a binary file), e.g.
 * "t.off:4: unexpected end of file in vertex 2 of the 3 the header announces". OFF: the
 * [ST][C][N]OFF keyword, optional "BINARY" (as OpenMesh writes it: little-endian), '#'
 * comments, the edge count optional; what follows a vertex's coordinates (and normal) or a
 * face's indices on its line (colours, texture coordinates) is skipped. PLY: ascii,
 * binary_little_endian and binary_big_endian; every element and property is read, x, y, z of
 * "vertex" and the list vertex_indices (or vertex_index) of "face" kept. */
cb_status cb_mesh_read(cb_mesh_t mesh, const char *path, cb_error *err);

#endif
