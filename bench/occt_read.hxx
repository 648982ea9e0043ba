// occt_read.hxx — reading a STEP file into one OCCT shape, shared by the OCCT comparators.
#ifndef CB_BENCH_OCCT_READ_HXX
#define CB_BENCH_OCCT_READ_HXX

#include <STEPControl_Reader.hxx>
#include <TopoDS_Shape.hxx>

// All roots of the file as one shape; false when it cannot be read or holds nothing.
static inline bool read_step(TopoDS_Shape &shape, const char *path)
{
    STEPControl_Reader reader;
    if (reader.ReadFile(path) != IFSelect_RetDone || reader.TransferRoots() <= 0)
        return false;
    shape = reader.OneShape();
    return !shape.IsNull();
}

#endif
