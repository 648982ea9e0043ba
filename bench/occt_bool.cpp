// Open CASCADE side of the Boolean comparison (built only when OCCT is installed; see
// scripts/setup-bench; run by bench_scenarios and bench_bool). For two STEP solids A and B and
// each of union, intersection and A - B (BRepAlgoAPI_Fuse, _Common, _Cut, parallel mode on): the
// median, least and largest wall time of RUNS runs, whether OCCT reports an error, the
// result's validity (BRepCheck_Analyzer), faces and volume by adaptive integration (the
// default Gauss rule is off by up to ~1% on rational faces). With OP, only that operation
// ("none": only read the files), so that the benchmarks can take each one's peak memory
// from a process of its own.
// Usage: occt_bool RUNS A.step B.step [union|intersection|difference|none]
// Output, one line per operation: OP MEDIAN_MS MIN_MS MAX_MS ERROR VALID FACES VOLUME
#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <TopExp_Explorer.hxx>

#include "bench/occt_read.hxx"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

static int count_faces(const TopoDS_Shape &s)
{
    int n = 0;
    for (TopExp_Explorer e(s, TopAbs_FACE); e.More(); e.Next())
        n++;
    return n;
}

static std::unique_ptr<BRepAlgoAPI_BooleanOperation> make_op(int k, const TopoDS_Shape &a,
                                                             const TopoDS_Shape &b)
{
    std::unique_ptr<BRepAlgoAPI_BooleanOperation> op;
    if (k == 0)
        op.reset(new BRepAlgoAPI_Fuse());
    else if (k == 1)
        op.reset(new BRepAlgoAPI_Common());
    else
        op.reset(new BRepAlgoAPI_Cut());
    TopTools_ListOfShape args, tools;
    args.Append(a);
    tools.Append(b);
    op->SetArguments(args);
    op->SetTools(tools);
    op->SetRunParallel(Standard_True);
    return op;
}

int main(int argc, char **argv)
{
    if (argc != 4 && argc != 5) {
        std::fprintf(stderr,
                     "usage: occt_bool RUNS A.step B.step [union|intersection|difference|none]\n");
        return 2;
    }
    int runs = std::max(1, std::atoi(argv[1]));
    TopoDS_Shape a, b;
    if (!read_step(a, argv[2]) || !read_step(b, argv[3])) {
        std::fprintf(stderr, "occt_bool: cannot read %s or %s\n", argv[2], argv[3]);
        return 2;
    }
    static const char *const names[3] = {"union", "intersection", "difference"};
    for (int k = 0; k < 3; k++) {
        if (argc == 5 && std::strcmp(argv[4], names[k]))
            continue;
        std::vector<double> t;
        TopoDS_Shape result;
        bool error = false;
        for (int r = 0; r < runs; r++) {
            auto t0 = std::chrono::steady_clock::now();
            std::unique_ptr<BRepAlgoAPI_BooleanOperation> op = make_op(k, a, b);
            op->Build();
            error = !op->IsDone() || op->HasErrors();
            if (!error)
                result = op->Shape();
            t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                            .count());
        }
        std::sort(t.begin(), t.end());
        double volume = 0;
        bool valid = false;
        int faces = 0;
        if (!error && !result.IsNull()) {
            GProp_GProps props;
            BRepGProp::VolumeProperties(result, props, 1e-9, Standard_False);
            volume = props.Mass();
            valid = BRepCheck_Analyzer(result).IsValid();
            faces = count_faces(result);
        }
        std::printf("%s %.3f %.3f %.3f %d %d %d %.17g\n", names[k], 1e3 * t[t.size() / 2],
                    1e3 * t.front(), 1e3 * t.back(), error ? 1 : 0, valid ? 1 : 0, faces, volume);
    }
    return 0;
}
