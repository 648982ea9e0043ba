/* mesh_openmesh.h — OpenMesh's file readers and writers behind a C interface (internal to io;
 * users call io/mesh.h). Implemented in mesh_openmesh.cpp; no C++ type or exception crosses. */
#ifndef CB_IO_MESH_OPENMESH_H
#define CB_IO_MESH_OPENMESH_H

#include "brep/mesh.h"
#include "brep/status.h"

/* Writes mesh with OpenMesh's writer for path's extension (one of .stl .obj .ply .off): text,
 * 17 significant digits of each coordinate rounded to float, except binary STL when
 * stl_binary is set. CB_ERR_IO with OpenMesh's complaint when the writer fails. */
cb_status cb_mesh_openmesh_write(const char *path, const cb_mesh_t mesh, int stl_binary,
                                 cb_error *err);

/* Appends the vertices and triangles of the file at path to mesh (empty on entry), reading
 * with OpenMesh's reader for its extension straight into mesh: faces are taken as given, so
 * non-manifold files are kept as they are. Errors as for cb_mesh_read. */
cb_status cb_mesh_openmesh_read(cb_mesh_t mesh, const char *path, cb_error *err);

#endif
