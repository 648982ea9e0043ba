/* mesh_file.c — mesh files by extension: the checks that need no OpenMesh, then the adapter. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "io/mesh.h"
#include "io/mesh_openmesh.h"

cb_status cb_mesh_format_of_path(cb_mesh_format *fmt, const char *path, cb_error *err)
{
    static const struct {
        const char *ext;
        cb_mesh_format fmt;
    } known[] = {{"stl", CB_MESH_STL}, {"obj", CB_MESH_OBJ}, {"ply", CB_MESH_PLY},
                 {"off", CB_MESH_OFF}};
    const char *dot = strrchr(path, '.');
    for (size_t k = 0; dot && k < sizeof known / sizeof *known; k++)
        if (!strcasecmp(dot + 1, known[k].ext)) {
            *fmt = known[k].fmt;
            return CB_OK;
        }
    return cb_error_set(err, CB_ERR_UNSUPPORTED,
                        "%s: unknown mesh format (known: .stl, .obj, .ply, .off)", path);
}

cb_status cb_mesh_write(const char *path, const cb_mesh_t mesh, const cb_mesh_write_options *opt,
                        cb_error *err)
{
    cb_mesh_format fmt;
    cb_status st = cb_mesh_format_of_path(&fmt, path, err);
    if (st)
        return st;
    /* OpenMesh only says that it failed; opening here first gives the user the reason. */
    FILE *f = fopen(path, "wb");
    if (!f)
        return cb_error_set(err, CB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    fclose(f);
    return cb_mesh_openmesh_write(path, mesh, fmt == CB_MESH_STL && !(opt && opt->stl_ascii),
                                  err);
}

cb_status cb_mesh_read(cb_mesh_t mesh, const char *path, cb_error *err)
{
    cb_mesh_clear(mesh);
    cb_mesh_format fmt;
    cb_status st = cb_mesh_format_of_path(&fmt, path, err);
    if (st)
        return st;
    FILE *f = fopen(path, "rb");
    if (!f)
        return cb_error_set(err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(f);
    st = cb_mesh_openmesh_read(mesh, path, err);
    if (!st && mesh->n_triangles == 0)
        st = cb_error_set(err, CB_ERR_PARSE, "%s: no triangles read", path);
    if (st)
        cb_mesh_clear(mesh);
    return st;
}
