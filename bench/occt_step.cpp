// Open CASCADE side of the STEP import comparison (built only when OCCT is installed; see
// scripts/setup-bench). For each file: median read+transfer time over N runs, solids, faces,
// validity (BRepCheck_Analyzer) and volume by adaptive integration (the default Gauss rule is
// off by up to ~1% on rational faces). Usage: occt_step N FILE...
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp_Explorer.hxx>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

static int count(const TopoDS_Shape &s, TopAbs_ShapeEnum kind)
{
    int n = 0;
    for (TopExp_Explorer e(s, kind); e.More(); e.Next())
        n++;
    return n;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: occt_step N FILE...\n");
        return 2;
    }
    int runs = std::atoi(argv[1]);
    if (runs < 1)
        runs = 1;
    std::printf("%-28s %9s %6s %6s %6s %16s\n", "file (OCCT 7.6)", "read ms", "solids", "faces",
                "valid", "volume");
    int status = 0;
    for (int i = 2; i < argc; i++) {
        std::vector<double> t;
        TopoDS_Shape shape;
        bool ok = true;
        for (int r = 0; r < runs && ok; r++) {
            auto t0 = std::chrono::steady_clock::now();
            STEPControl_Reader reader;
            ok = reader.ReadFile(argv[i]) == IFSelect_RetDone && reader.TransferRoots() > 0;
            shape = reader.OneShape();
            t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                            .count());
        }
        if (!ok) {
            std::printf("%-28s read failed\n", argv[i]);
            status = 1;
            continue;
        }
        std::sort(t.begin(), t.end());
        GProp_GProps props;
        BRepGProp::VolumeProperties(shape, props, 1e-9, Standard_False);
        const char *name = argv[i];
        for (const char *p = argv[i]; *p; p++)
            if (*p == '/')
                name = p + 1;
        std::printf("%-28s %9.2f %6d %6d %6s %16.9g\n", name, 1e3 * t[t.size() / 2],
                    count(shape, TopAbs_SOLID), count(shape, TopAbs_FACE),
                    BRepCheck_Analyzer(shape).IsValid() ? "yes" : "no", props.Mass());
    }
    return status;
}
