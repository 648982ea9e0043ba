// Open CASCADE side of the SSI comparison (built only when OCCT is installed; run by
// bench_ssi_cases). Intersects two surfaces with GeomInt_IntSS, the engine behind
// GeomAPI_IntSS (which returns its curves but not its isolated points), RUNS times, and prints
// the median, least and largest wall time, then the curves sampled as polylines and the
// isolated points of the last run.
// Usage: occt_ssi RUNS TOL PAIR.txt
// PAIR.txt holds two surfaces, each one of
//   nurbs DEG_U DEG_V N_U N_V   then the N_U + DEG_U + 1 u knots, the N_V + DEG_V + 1 v knots
//                               and N_U * N_V lines "x y z w" (Euclidean point, weight; u outer)
//   torus OX OY OZ  NX NY NZ  XX XY XZ  R r   (centre, axis, reference direction, radii)
// Output: MEDIAN_MS MIN_MS MAX_MS DONE N_CURVES N_POINTS, then per curve "L n" and n lines
// "x y z", then per isolated point "P x y z".
#include <Geom_BSplineSurface.hxx>
#include <Geom_Curve.hxx>
#include <Geom_ToroidalSurface.hxx>
#include <GeomInt_IntSS.hxx>
#include <Precision.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Ax3.hxx>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

// Distinct knots and multiplicities of a flat knot vector.
static void split_knots(const std::vector<double> &flat, TColStd_Array1OfReal *&k,
                        TColStd_Array1OfInteger *&m)
{
    std::vector<double> v;
    std::vector<int> mult;
    for (double x : flat) {
        if (!v.empty() && x == v.back()) {
            mult.back()++;
        } else {
            v.push_back(x);
            mult.push_back(1);
        }
    }
    k = new TColStd_Array1OfReal(1, (int)v.size());
    m = new TColStd_Array1OfInteger(1, (int)v.size());
    for (size_t i = 0; i < v.size(); i++) {
        k->SetValue((int)i + 1, v[i]);
        m->SetValue((int)i + 1, mult[i]);
    }
}

static Handle(Geom_Surface) read_surface(FILE *f)
{
    char kind[16];
    if (std::fscanf(f, "%15s", kind) != 1)
        return nullptr;
    if (!std::strcmp(kind, "torus")) {
        double v[11];
        for (double &x : v)
            if (std::fscanf(f, "%lf", &x) != 1)
                return nullptr;
        gp_Ax3 ax(gp_Pnt(v[0], v[1], v[2]), gp_Dir(v[3], v[4], v[5]), gp_Dir(v[6], v[7], v[8]));
        return new Geom_ToroidalSurface(ax, v[9], v[10]);
    }
    int du, dv, nu, nv;
    if (std::strcmp(kind, "nurbs") || std::fscanf(f, "%d %d %d %d", &du, &dv, &nu, &nv) != 4 ||
        du < 1 || dv < 1 || nu <= du || nv <= dv)
        return nullptr;
    std::vector<double> ku(nu + du + 1), kv(nv + dv + 1);
    for (double &x : ku)
        if (std::fscanf(f, "%lf", &x) != 1)
            return nullptr;
    for (double &x : kv)
        if (std::fscanf(f, "%lf", &x) != 1)
            return nullptr;
    TColgp_Array2OfPnt poles(1, nu, 1, nv);
    TColStd_Array2OfReal weights(1, nu, 1, nv);
    bool rational = false;
    for (int i = 1; i <= nu; i++)
        for (int j = 1; j <= nv; j++) {
            double x, y, z, w;
            if (std::fscanf(f, "%lf %lf %lf %lf", &x, &y, &z, &w) != 4)
                return nullptr;
            poles.SetValue(i, j, gp_Pnt(x, y, z));
            weights.SetValue(i, j, w);
            rational = rational || w != 1;
        }
    TColStd_Array1OfReal *uk, *vk;
    TColStd_Array1OfInteger *um, *vm;
    split_knots(ku, uk, um);
    split_knots(kv, vk, vm);
    Handle(Geom_Surface) s;
    if (rational)
        s = new Geom_BSplineSurface(poles, weights, *uk, *vk, *um, *vm, du, dv);
    else
        s = new Geom_BSplineSurface(poles, *uk, *vk, *um, *vm, du, dv);
    delete uk;
    delete vk;
    delete um;
    delete vm;
    return s;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        std::fprintf(stderr, "usage: occt_ssi RUNS TOL PAIR.txt\n");
        return 2;
    }
    int runs = std::max(1, std::atoi(argv[1]));
    double tol = std::atof(argv[2]);
    FILE *f = std::fopen(argv[3], "r");
    Handle(Geom_Surface) a, b;
    if (f) {
        a = read_surface(f);
        b = read_surface(f);
        std::fclose(f);
    }
    if (a.IsNull() || b.IsNull()) {
        std::fprintf(stderr, "occt_ssi: cannot read %s\n", argv[3]);
        return 2;
    }
    std::vector<double> t;
    std::unique_ptr<GeomInt_IntSS> last;
    for (int r = 0; r < runs; r++) {
        auto t0 = std::chrono::steady_clock::now();
        last.reset(new GeomInt_IntSS());
        last->Perform(a, b, tol, Standard_True, Standard_False, Standard_False);
        t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    bool done = last->IsDone();
    int nl = done ? last->NbLines() : 0, np = done ? last->NbPoints() : 0;
    std::printf("%.3f %.3f %.3f %d %d %d\n", 1e3 * t[t.size() / 2], 1e3 * t.front(),
                1e3 * t.back(), done ? 1 : 0, nl, np);
    // Curves as polylines of 500 uniform parameter steps (an unbounded curve, which OCCT
    // gives only for lines of analytic pairs, is cut at +-1e3).
    const int steps = 500;
    for (int i = 1; i <= nl; i++) {
        const Handle(Geom_Curve) &c = last->Line(i);
        double u0 = std::max(c->FirstParameter(), -1e3), u1 = std::min(c->LastParameter(), 1e3);
        std::printf("L %d\n", steps + 1);
        for (int k = 0; k <= steps; k++) {
            gp_Pnt p = c->Value(u0 + (u1 - u0) * k / steps);
            std::printf("%.17g %.17g %.17g\n", p.X(), p.Y(), p.Z());
        }
    }
    for (int i = 1; i <= np; i++) {
        gp_Pnt p = last->Point(i);
        std::printf("P %.17g %.17g %.17g\n", p.X(), p.Y(), p.Z());
    }
    return 0;
}
