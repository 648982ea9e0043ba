// Open CASCADE side of the model SSI comparison (built only when OCCT is installed; run by
// bench_ssi_models). Reads two STEP files, turns B by DEG degrees about the axis (AX, AY, AZ)
// through the origin and then moves it by (TX, TY, TZ) (millimetres: OCCT's reader converts
// every file to mm), and intersects the two with BRepAlgoAPI_Section RUNS times. The section
// is built with approximated 3D curves and pcurves on both arguments, since Colibri's curves
// carry points and parameters on both faces. MODE: "parallel" (SetRunParallel, all
// hardware threads), "serial", or "none" (only read the files, so that the caller can take
// the peak memory of the reading alone from a process of its own).
// Usage: occt_section RUNS A.step B.step AX AY AZ DEG TX TY TZ parallel|serial|none
// Output: MEDIAN_MS MIN_MS MAX_MS DONE HAS_ERRORS EDGES VERTICES LENGTH_MM (of the last run)
#include <BRepAlgoAPI_Section.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <gp_Ax1.hxx>
#include <gp_Trsf.hxx>

#include "bench/occt_read.hxx"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

int main(int argc, char **argv)
{
    if (argc != 12 || (std::strcmp(argv[11], "parallel") && std::strcmp(argv[11], "serial") &&
                       std::strcmp(argv[11], "none"))) {
        std::fprintf(stderr, "usage: occt_section RUNS A.step B.step AX AY AZ DEG TX TY TZ "
                             "parallel|serial|none\n");
        return 2;
    }
    int runs = std::max(1, std::atoi(argv[1]));
    double v[7];
    for (int i = 0; i < 7; i++)
        v[i] = std::atof(argv[4 + i]);
    TopoDS_Shape a, b;
    if (!read_step(a, argv[2]) || !read_step(b, argv[3])) {
        std::fprintf(stderr, "occt_section: cannot read %s or %s\n", argv[2], argv[3]);
        return 2;
    }
    if (!std::strcmp(argv[11], "none"))
        return 0;
    gp_Trsf turn, shift;
    if (v[3] != 0)
        turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(v[0], v[1], v[2])), v[3] * M_PI / 180);
    shift.SetTranslation(gp_Vec(v[4], v[5], v[6]));
    // Copied, so that B's geometry itself is moved as Colibri's is, not just located.
    b = BRepBuilderAPI_Transform(b, shift * turn, Standard_True).Shape();
    bool parallel = !std::strcmp(argv[11], "parallel");
    std::vector<double> t;
    TopoDS_Shape section;
    bool done = false, errors = false;
    for (int r = 0; r < runs; r++) {
        auto t0 = std::chrono::steady_clock::now();
        BRepAlgoAPI_Section op(a, b, Standard_False);
        op.Approximation(Standard_True);
        op.ComputePCurveOn1(Standard_True);
        op.ComputePCurveOn2(Standard_True);
        op.SetRunParallel(parallel ? Standard_True : Standard_False);
        op.Build();
        done = op.IsDone();
        errors = op.HasErrors();
        if (done)
            section = op.Shape();
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    TopTools_IndexedMapOfShape edges, vertices;
    double length = 0;
    if (done && !section.IsNull()) {
        TopExp::MapShapes(section, TopAbs_EDGE, edges);
        TopExp::MapShapes(section, TopAbs_VERTEX, vertices);
        GProp_GProps props;
        BRepGProp::LinearProperties(section, props);
        length = props.Mass();
    }
    std::printf("%.3f %.3f %.3f %d %d %d %d %.17g\n", 1e3 * t[t.size() / 2], 1e3 * t.front(),
                1e3 * t.back(), done ? 1 : 0, errors ? 1 : 0, edges.Extent(), vertices.Extent(),
                length);
    return 0;
}
