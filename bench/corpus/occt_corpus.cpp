// occt_corpus — a randomized differential corpus of primitive Booleans written by Open CASCADE
// (built only when OCCT is installed; see scripts/setup-bench and bench/README.md).
//
// Every configuration is built in a local frame where V(A n B) has a closed form (or a 1-D
// integral of one, evaluated by Gauss-Legendre quadrature of growing order to 1e-14), with its
// sizes and offsets drawn at random inside the ranges that keep its class; then one rigid
// motion moves both solids (volumes do not change): pose "axis" is no motion, "translated" a
// random translation, "rotated" a random unit quaternion (uniform on the sphere: irrational
// angles about a generic axis) and a translation. Faces come "analytic" (as OCCT's primitives
// make them: seams, degenerate pole edges, apex vertices; ellipsoids are a sphere under a
// non-uniform scaling, which OCCT turns into B-spline faces) or "nurbs"
// (BRepBuilderAPI_NurbsConvert of each moved solid). Each solid is written by OCCT's STEP writer
// (STEPControl_AsIs), so the files are as another CAD system writes them.
//
// Usage: occt_corpus OUTDIR [--seed S] [--n-per-config K] [--subset] [--verify] [--only SUBSTR]
//   OUTDIR/<id>_a.step, <id>_b.step and OUTDIR/cases.json (one case per line: id, config, draw,
//   pose, faces, files, motion, va, vb, vi, union, intersection, difference, touching, bar
//   scale, description).
//   --seed S (default 1): the corpus is a function of S alone; every case draws from a
//     generator seeded by (S, configuration, draw), so a subset holds the same cases as the
//     whole corpus.
//   --n-per-config K (default 4): draws per configuration; each draw gives 6 cases (3 poses x
//     analytic/nurbs).
//   --subset: only draw 0 of each configuration and 4 of its 6 pose/face combinations (every
//     pose and both face kinds in each configuration): the committed ctest subset.
//   --verify: checks every formula against OCCT: for each draw, the axis-aligned analytic case's
//     V(A n B) by BRepAlgoAPI_Common and BRepGProp (adaptive), and V(A), V(B) of every case as
//     written; prints the worst disagreement per configuration. Writes nothing unless OUTDIR is
//     given as well (OUTDIR "-" : verify only).
//   --only SUBSTR: only configurations whose name contains SUBSTR.
#include <APIHeaderSection_MakeHeader.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_GTransform.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <GProp_GProps.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <StepData_StepModel.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Ax2.hxx>
#include <gp_GTrsf.hxx>
#include <gp_Quaternion.hxx>
#include <gp_Trsf.hxx>

#include <algorithm>
#include <cmath>
#include <cctype>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

const double PI = 3.14159265358979323846;

// ---------------------------------------------------------------- random numbers ------------
// splitmix64: the same numbers on every platform (std's distributions are not specified).
struct Rng {
    uint64_t s;
    uint64_t next()
    {
        uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    double u01() { return (double)(next() >> 11) * 0x1.0p-53; }
    double u(double lo, double hi) { return lo + (hi - lo) * u01(); }
};

uint64_t hash_str(const char *s)
{
    uint64_t h = 1469598103934665603ULL; // FNV-1a
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ULL;
    return h;
}

Rng rng_for(uint64_t seed, const char *config, int draw, int pose)
{
    Rng r{seed * 0x2545f4914f6cdd1dULL ^ hash_str(config) ^
          ((uint64_t)(draw + 1) * 0x9e3779b97f4a7c15ULL) ^ ((uint64_t)(pose + 7) << 40)};
    r.next();
    return r;
}

gp_Dir random_dir(Rng &r)
{
    for (;;) {
        double x = r.u(-1, 1), y = r.u(-1, 1), z = r.u(-1, 1), n = x * x + y * y + z * z;
        if (n > 0.01 && n <= 1)
            return gp_Dir(x, y, z);
    }
}

// A random unit vector perpendicular to d.
gp_Dir random_perp(Rng &r, const gp_Dir &d)
{
    for (;;) {
        gp_Vec v(random_dir(r));
        gp_Vec w = v - gp_Vec(d) * v.Dot(gp_Vec(d));
        if (w.Magnitude() > 0.1)
            return gp_Dir(w);
    }
}

// ---------------------------------------------------------------- quadrature ----------------
// Gauss-Legendre with n points on [a, b] (nodes by Newton's method on P_n).
double gauss_legendre(double (*f)(double, const double *), const double *p, double a, double b,
                      int n)
{
    double sum = 0;
    for (int i = 1; i <= n; i++) {
        double x = std::cos(PI * (i - 0.25) / (n + 0.5)), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = x;
            for (int k = 2; k <= n; k++) {
                double pk = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = pk;
            }
            dp = n * (x * p1 - p0) / (x * x - 1);
            double dx = p1 / dp;
            x -= dx;
            if (std::fabs(dx) < 1e-16)
                break;
        }
        double w = 2 / ((1 - x * x) * dp * dp);
        sum += w * f(0.5 * (b - a) * x + 0.5 * (a + b), p);
    }
    return 0.5 * (b - a) * sum;
}

// The integral of an analytic integrand to a relative 1e-14: orders 16, 32, ... until two
// agree (the error of Gauss-Legendre falls geometrically with n on analytic functions).
double integrate(double (*f)(double, const double *), const double *p, double a, double b)
{
    double prev = gauss_legendre(f, p, a, b, 16);
    for (int n = 32; n <= 1024; n *= 2) {
        double cur = gauss_legendre(f, p, a, b, n);
        if (std::fabs(cur - prev) <= 1e-14 * std::fabs(cur))
            return cur;
        prev = cur;
    }
    std::fprintf(stderr, "occt_corpus: quadrature did not converge\n");
    std::exit(1);
}

// ---------------------------------------------------------------- closed forms --------------
double v_sphere(double r) { return 4 * PI * r * r * r / 3; }
double v_cyl(double r, double h) { return PI * r * r * h; }
double v_cone(double r, double h) { return PI * r * r * h / 3; }
double v_torus(double R, double r) { return 2 * PI * PI * R * r * r; }

// Area of the part {x >= h} of a disc of radius r centred at x = 0 (|h| <= r).
double disc_segment(double r, double h) { return r * r * std::acos(h / r) - h * std::sqrt(r * r - h * h); }

// Area of the lens where two discs of radii r1, r2 at distance d overlap.
double lens_area(double r1, double r2, double d)
{
    double a1 = std::acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1));
    double a2 = std::acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2));
    double k = (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2);
    return r1 * r1 * a1 + r2 * r2 * a2 - 0.5 * std::sqrt(k);
}

// Volume of the lens of two balls of radii r1, r2 at distance d (|r1 - r2| < d < r1 + r2).
double sphere_lens(double r1, double r2, double d)
{
    double s = r1 + r2 - d;
    return PI * s * s * (d * d + 2 * d * r2 - 3 * r2 * r2 + 2 * d * r1 + 6 * r1 * r2 - 3 * r1 * r1) /
           (12 * d);
}

// Cap {z >= h} of a ball of radius r (|h| <= r).
double sphere_cap(double r, double h)
{
    double c = r - h;
    return PI * c * c * (3 * r - c) / 3;
}

// Antiderivatives over the torus's disc section: F' = sqrt(r^2 - s^2), G' = s sqrt(r^2 - s^2).
double torus_F(double r, double s) { return 0.5 * s * std::sqrt(r * r - s * s) + 0.5 * r * r * std::asin(s / r); }
double torus_G(double r, double s) { return -std::pow(r * r - s * s, 1.5) / 3; }

// Part {z >= h} of a torus (major R, minor r, axis z): each slice z is an annulus of area
// 4 pi R sqrt(r^2 - z^2).
double torus_above(double R, double r, double h) { return 4 * PI * R * (torus_F(r, r) - torus_F(r, h)); }

// Part of the torus within distance rho of its axis (R - r <= rho <= R + r): Pappus over the
// disc section, 2 pi rho' dA with s = rho' - R.
double torus_within(double R, double r, double rho)
{
    double s = rho - R;
    return 4 * PI * (R * (torus_F(r, s) - torus_F(r, -r)) + torus_G(r, s) - torus_G(r, -r));
}

// Integrands of the quadrature checks (p: parameters).
double f_steinmetz(double t, const double *p)
{
    // Cylinders of radii R = p[0] (axis x) and r = p[1] (axis y): the slice z = r sin t is a
    // rectangle 2 sqrt(r^2 - z^2) by 2 sqrt(R^2 - z^2); dz = r cos t dt.
    double R = p[0], r = p[1], c = std::cos(t), s = std::sin(t);
    return 4 * r * r * c * c * std::sqrt(R * R - r * r * s * s);
}
double steinmetz(double R, double r)
{
    double p[2] = {R, r};
    return integrate(f_steinmetz, p, -PI / 2, PI / 2);
}
double f_torus_slice(double t, const double *p)
{
    // Slice z = r sin t of the torus: 4 pi R sqrt(r^2 - z^2), dz = r cos t dt.
    double R = p[0], r = p[1], c = std::cos(t);
    return 4 * PI * R * r * c * r * c;
}
double f_torus_shell(double t, const double *p)
{
    // Cylindrical shells rho' = R + r sin t: 2 pi rho' 2 sqrt(r^2 - s^2) ds, ds = r cos t dt.
    double R = p[0], r = p[1], c = std::cos(t), s = r * std::sin(t);
    return 2 * PI * (R + s) * 2 * r * c * r * c;
}

// ---------------------------------------------------------------- OCCT solids ---------------
TopoDS_Shape box(double x, double y, double z, double dx, double dy, double dz)
{
    return BRepPrimAPI_MakeBox(gp_Pnt(x, y, z), dx, dy, dz).Shape();
}
TopoDS_Shape sphere(const gp_Pnt &c, double r, const gp_Dir &axis)
{
    return BRepPrimAPI_MakeSphere(gp_Ax2(c, axis), r).Shape();
}
// Axis from base along dir for h; the seam on the line base + r xdir (xdir is made
// perpendicular to dir).
TopoDS_Shape cylinder(const gp_Pnt &base, const gp_Dir &dir, const gp_Dir &xdir, double r, double h)
{
    return BRepPrimAPI_MakeCylinder(gp_Ax2(base, dir, xdir), r, h).Shape();
}
TopoDS_Shape cone(const gp_Pnt &base, double R, double h)
{
    return BRepPrimAPI_MakeCone(gp_Ax2(base, gp::DZ()), R, 0, h).Shape();
}
TopoDS_Shape torus(const gp_Dir &xdir, double R, double r)
{
    return BRepPrimAPI_MakeTorus(gp_Ax2(gp::Origin(), gp::DZ(), xdir), R, r).Shape();
}
TopoDS_Shape ellipsoid(double a, double b, double c, const gp_Dir &axis)
{
    gp_GTrsf g;
    g.SetValue(1, 1, a);
    g.SetValue(2, 2, b);
    g.SetValue(3, 3, c);
    return BRepBuilderAPI_GTransform(sphere(gp::Origin(), 1, axis), g, Standard_True).Shape();
}

// ---------------------------------------------------------------- configurations ------------
struct Built {
    TopoDS_Shape a, b;
    double va = 0, vb = 0, vi = 0;
    bool touching = false;
    double check = NAN; // an independent quadrature of vi where the closed form has one
    // Where OCCT's Common of a and b is not exact (B-spline faces), a pair of analytic solids
    // whose V(A n B) times alt_scale is V(A n B) (the ellipsoid scaled back to its sphere).
    TopoDS_Shape alt_a, alt_b;
    double alt_scale = NAN;
    std::string desc;
};

std::string fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char *f, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

// A sphere's own axis: OCCT's default (z: poles and seam where the configuration's axes are)
// on even draws, a random one on odd draws.
gp_Dir sphere_axis(Rng &r, int draw) { return draw % 2 ? random_dir(r) : gp::DZ(); }

typedef Built (*builder)(Rng &r, int draw);

Built box_overlap(Rng &r, int)
{
    Built c;
    double a[3], o[3], b[3], vi = 1;
    for (int i = 0; i < 3; i++) {
        a[i] = r.u(1, 2.2);
        o[i] = r.u(0.25, 0.75) * a[i];
        b[i] = a[i] - o[i] + r.u(0.25, 1.1);
        vi *= a[i] - o[i];
    }
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = box(o[0], o[1], o[2], b[0], b[1], b[2]);
    c.va = a[0] * a[1] * a[2];
    c.vb = b[0] * b[1] * b[2];
    c.vi = vi;
    c.desc = fmt("boxes overlapping in a corner: V(A n B) = product of the overlaps");
    return c;
}

Built box_stacked(Rng &r, int)
{
    Built c;
    double a[3], o[2], b[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1, 2.2);
    for (int i = 0; i < 2; i++) {
        o[i] = r.u(0.25, 0.75) * a[i];
        b[i] = a[i] - o[i] + r.u(0.25, 1.1);
    }
    b[2] = r.u(0.8, 2);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = box(o[0], o[1], a[2], b[0], b[1], b[2]);
    c.va = a[0] * a[1] * a[2];
    c.vb = b[0] * b[1] * b[2];
    c.vi = 0;
    c.desc = "box B standing on A's top face, sharing part of it (coincident faces, VI = 0)";
    return c;
}

Built box_coplanar(Rng &r, int)
{
    Built c;
    double a[3], o[2], b[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1, 2.2);
    for (int i = 0; i < 2; i++) {
        o[i] = r.u(0.25, 0.75) * a[i];
        b[i] = a[i] - o[i] + r.u(0.25, 1.1);
    }
    b[2] = r.u(0.8, 2.2);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = box(o[0], o[1], 0, b[0], b[1], b[2]);
    c.va = a[0] * a[1] * a[2];
    c.vb = b[0] * b[1] * b[2];
    c.vi = (a[0] - o[0]) * (a[1] - o[1]) * std::min(a[2], b[2]);
    c.desc = "overlapping boxes on one bottom plane (coincident faces in part)";
    return c;
}

Built box_edge(Rng &r, int)
{
    Built c;
    double a[3], b[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1, 2.2), b[i] = r.u(0.8, 2);
    double o = r.u(0.25, 0.75) * a[1];
    b[1] = a[1] - o + r.u(0.25, 1.1);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = box(a[0], o, a[2], b[0], b[1], b[2]);
    c.va = a[0] * a[1] * a[2];
    c.vb = b[0] * b[1] * b[2];
    c.touching = true;
    c.desc = "boxes touching along part of an edge (VI = 0; the union touches itself on a line)";
    return c;
}

Built box_corner(Rng &r, int)
{
    Built c;
    double a[3], b[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1, 2.2), b[i] = r.u(0.8, 2);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = box(a[0], a[1], a[2], b[0], b[1], b[2]);
    c.va = a[0] * a[1] * a[2];
    c.vb = b[0] * b[1] * b[2];
    c.touching = true;
    c.desc = "boxes touching at a corner (VI = 0; the union touches itself at a point)";
    return c;
}

// Direction of the second sphere's centre: local x on even draws, random on odd ones.
gp_Dir centre_dir(Rng &r, int draw) { return draw % 2 ? random_dir(r) : gp::DX(); }

Built sphere_lens(Rng &r, int draw)
{
    Built c;
    double r1 = r.u(1, 1.8), r2 = r.u(0.6, 1.6);
    double d = r.u(std::fabs(r1 - r2) + 0.2, r1 + r2 - 0.2);
    gp_Dir dir = centre_dir(r, draw);
    c.a = sphere(gp::Origin(), r1, sphere_axis(r, draw));
    c.b = sphere(gp_Pnt(gp_XYZ(dir.XYZ()) * d), r2, sphere_axis(r, draw));
    c.va = v_sphere(r1);
    c.vb = v_sphere(r2);
    c.vi = sphere_lens(r1, r2, d);
    c.desc = fmt("spheres r1 %.4f, r2 %.4f at distance %.4f: lens", r1, r2, d);
    return c;
}

Built sphere_touch(Rng &r, int draw)
{
    Built c;
    double r1 = r.u(1, 1.8), r2 = r.u(0.6, 1.6), d = r1 + r2;
    gp_Dir dir = centre_dir(r, draw);
    c.a = sphere(gp::Origin(), r1, sphere_axis(r, draw));
    c.b = sphere(gp_Pnt(gp_XYZ(dir.XYZ()) * d), r2, sphere_axis(r, draw));
    c.va = v_sphere(r1);
    c.vb = v_sphere(r2);
    c.touching = true;
    c.desc = fmt("spheres r1 %.4f, r2 %.4f touching externally at a point", r1, r2);
    return c;
}

Built sphere_inside(Rng &r, int draw)
{
    Built c;
    double r1 = r.u(1, 1.8), r2 = r.u(0.3, 0.8) * r1, d = r1 - r2;
    gp_Dir dir = centre_dir(r, draw);
    c.a = sphere(gp::Origin(), r1, sphere_axis(r, draw));
    c.b = sphere(gp_Pnt(gp_XYZ(dir.XYZ()) * d), r2, sphere_axis(r, draw));
    c.va = v_sphere(r1);
    c.vb = v_sphere(r2);
    c.vi = c.vb;
    c.touching = true;
    c.desc = fmt("sphere r2 %.4f inside sphere r1 %.4f touching it internally (A - B: a void "
                 "touching the boundary at a point)",
                 r2, r1);
    return c;
}

Built sphere_cap(Rng &r, int draw)
{
    Built c;
    double R = r.u(1, 1.8), h = r.u(-0.7, 0.7) * R;
    double x0 = -R - r.u(0.2, 1), x1 = R + r.u(0.2, 1), y0 = -R - r.u(0.2, 1), y1 = R + r.u(0.2, 1);
    double z1 = R + r.u(0.2, 1);
    c.a = sphere(gp::Origin(), R, sphere_axis(r, draw));
    c.b = box(x0, y0, h, x1 - x0, y1 - y0, z1 - h);
    c.va = v_sphere(R);
    c.vb = (x1 - x0) * (y1 - y0) * (z1 - h);
    c.vi = sphere_cap(R, h);
    c.desc = fmt("sphere r %.4f, box above the plane z = %.4f: cap", R, h);
    return c;
}

Built sphere_corner(Rng &r, int draw)
{
    Built c;
    double a[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1.4, 2.4);
    double R = r.u(0.4, 0.85) * std::min(a[0], std::min(a[1], a[2]));
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = sphere(gp::Origin(), R, sphere_axis(r, draw));
    c.va = a[0] * a[1] * a[2];
    c.vb = v_sphere(R);
    c.vi = c.vb / 8;
    c.desc = fmt("sphere r %.4f centred on a box corner: 1/8%s", R,
                 draw % 2 ? "" : " (its seam and poles on the box's faces and edge)");
    return c;
}

Built sphere_edge(Rng &r, int draw)
{
    Built c;
    double a[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1.4, 2.4);
    double t = r.u(0.4, 0.6) * a[0];
    double R = r.u(0.35, 0.85) * std::min(std::min(t, a[0] - t), std::min(a[1], a[2]));
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = sphere(gp_Pnt(t, 0, 0), R, sphere_axis(r, draw));
    c.va = a[0] * a[1] * a[2];
    c.vb = v_sphere(R);
    c.vi = c.vb / 4;
    c.desc = fmt("sphere r %.4f centred on a box edge: 1/4", R);
    return c;
}

Built sphere_on_face(Rng &r, int draw)
{
    Built c;
    double a[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1.4, 2.4);
    double R = r.u(0.4, 1.2);
    gp_Pnt ctr(r.u(0.3, 0.7) * a[0], r.u(0.3, 0.7) * a[1], a[2] + R);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = sphere(ctr, R, sphere_axis(r, draw));
    c.va = a[0] * a[1] * a[2];
    c.vb = v_sphere(R);
    c.touching = true;
    c.desc = fmt("sphere r %.4f lying on a box face, touching it at one point%s", R,
                 draw % 2 ? "" : " (its pole)");
    return c;
}

// Seam direction of a cylinder: fixed on even draws (the given one), random on odd ones.
gp_Dir seam(Rng &r, int draw, const gp_Dir &axis, const gp_Dir &fixed)
{
    return draw % 2 ? random_perp(r, axis) : fixed;
}

Built cyl_through(Rng &r, int draw)
{
    Built c;
    double a[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1.4, 2.4);
    double R = r.u(0.2, 0.4) * std::min(a[0], a[1]);
    double cx = r.u(R + 0.1, a[0] - R - 0.1), cy = r.u(R + 0.1, a[1] - R - 0.1);
    double z0 = -r.u(0.2, 1), z1 = a[2] + r.u(0.2, 1);
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    c.b = cylinder(gp_Pnt(cx, cy, z0), gp::DZ(), seam(r, draw, gp::DZ(), gp::DX()), R, z1 - z0);
    c.va = a[0] * a[1] * a[2];
    c.vb = v_cyl(R, z1 - z0);
    c.vi = v_cyl(R, a[2]);
    c.desc = fmt("cylinder r %.4f through a box, perpendicular to a face", R);
    return c;
}

Built cyl_lengthwise(Rng &r, int draw)
{
    Built c;
    double R = r.u(0.5, 1.2), L = r.u(1.5, 3), h = r.u(-0.7, 0.7) * R;
    double x0, x1;
    if (draw % 2) { // the cylinder longer than the box
        x0 = r.u(0.2, 0.4) * L;
        x1 = L - r.u(0.2, 0.4) * L;
    } else {
        x0 = -r.u(0.2, 0.8);
        x1 = L + r.u(0.2, 0.8);
    }
    double y1 = R + r.u(0.2, 0.8), z0 = -R - r.u(0.2, 0.8), z1 = R + r.u(0.2, 0.8);
    c.a = cylinder(gp::Origin(), gp::DX(), seam(r, draw, gp::DX(), gp::DY()), R, L);
    c.b = box(x0, h, z0, x1 - x0, y1 - h, z1 - z0);
    c.va = v_cyl(R, L);
    c.vb = (x1 - x0) * (y1 - h) * (z1 - z0);
    c.vi = disc_segment(R, h) * (std::min(x1, L) - std::max(x0, 0.0));
    c.desc = fmt("cylinder r %.4f cut lengthwise by the plane y = %.4f: segment x length", R, h);
    return c;
}

Built cyl_on_face(Rng &r, int draw)
{
    Built c;
    double a[3];
    for (int i = 0; i < 3; i++)
        a[i] = r.u(1.4, 2.4);
    double R = r.u(0.3, 0.7), x0 = r.u(0.1, 0.5) * a[0], L = r.u(0.8, 2);
    double y = r.u(0.3, 0.7) * a[1];
    c.a = box(0, 0, 0, a[0], a[1], a[2]);
    // Even draws: the seam on the contact line.
    c.b = cylinder(gp_Pnt(x0, y, a[2] + R), gp::DX(), seam(r, draw, gp::DX(), -gp::DZ()), R, L);
    c.va = a[0] * a[1] * a[2];
    c.vb = v_cyl(R, L);
    c.touching = true;
    c.desc = fmt("cylinder r %.4f lying on a box face, tangent along a line%s", R,
                 draw % 2 ? "" : " (its seam)");
    return c;
}

Built cyl_steinmetz(Rng &r, int draw)
{
    Built c;
    double R = r.u(0.6, 1.4);
    double xa = R + r.u(0.3, 1), xb = R + r.u(0.3, 1), ya = R + r.u(0.3, 1), yb = R + r.u(0.3, 1);
    // Even draws: both seams through the point (0, 0, R) where the two surfaces touch.
    c.a = cylinder(gp_Pnt(-xa, 0, 0), gp::DX(), seam(r, draw, gp::DX(), gp::DZ()), R, xa + xb);
    c.b = cylinder(gp_Pnt(0, -ya, 0), gp::DY(), seam(r, draw, gp::DY(), gp::DZ()), R, ya + yb);
    c.va = v_cyl(R, xa + xb);
    c.vb = v_cyl(R, ya + yb);
    c.vi = 16 * R * R * R / 3;
    c.check = steinmetz(R, R);
    // B covers A's whole section at x = 0, so A - B is two solids touching at (0, 0, +-R).
    c.touching = true;
    c.desc = fmt("Steinmetz bicylinder r %.4f%s (A - B: two solids touching at two points)", R,
                 draw % 2 ? "" : " (seams through the contact points)");
    return c;
}

Built cyl_unequal(Rng &r, int draw)
{
    Built c;
    double R = r.u(1, 1.5), rr = r.u(0.45, 0.85) * R;
    double xa = rr + r.u(0.3, 1), xb = rr + r.u(0.3, 1), ya = R + r.u(0.3, 1), yb = R + r.u(0.3, 1);
    // Even draws: A's seam through (+-r, R, 0), B's through (0, +-sqrt(R^2 - r^2), r): points of
    // the intersection curves.
    c.a = cylinder(gp_Pnt(-xa, 0, 0), gp::DX(), seam(r, draw, gp::DX(), gp::DY()), R, xa + xb);
    c.b = cylinder(gp_Pnt(0, -ya, 0), gp::DY(), seam(r, draw, gp::DY(), gp::DZ()), rr, ya + yb);
    c.va = v_cyl(R, xa + xb);
    c.vb = v_cyl(rr, ya + yb);
    c.vi = steinmetz(R, rr);
    c.desc = fmt("crossing cylinders R %.4f, r %.4f (integral of 4 sqrt(r^2-z^2) sqrt(R^2-z^2))%s",
                 R, rr, draw % 2 ? "" : " (seams through points of the curves)");
    return c;
}

Built cyl_parallel(Rng &r, int draw)
{
    Built c;
    double r1 = r.u(0.6, 1.2), r2 = r.u(0.5, 1.1);
    double d = r.u(std::fabs(r1 - r2) + 0.15, r1 + r2 - 0.15), phi = r.u(0, 2 * PI);
    double H1 = r.u(1.5, 2.5), z0 = r.u(0.2, 0.6) * H1, H2 = H1 - z0 + r.u(0.2, 1);
    c.a = cylinder(gp::Origin(), gp::DZ(), seam(r, draw, gp::DZ(), gp::DX()), r1, H1);
    c.b = cylinder(gp_Pnt(d * std::cos(phi), d * std::sin(phi), z0), gp::DZ(),
                   seam(r, draw, gp::DZ(), gp::DX()), r2, H2);
    c.va = v_cyl(r1, H1);
    c.vb = v_cyl(r2, H2);
    c.vi = lens_area(r1, r2, d) * (H1 - z0);
    c.desc = fmt("parallel cylinders r1 %.4f, r2 %.4f, axes %.4f apart: lens area x length", r1,
                 r2, d);
    return c;
}

Built sphere_in_cyl(Rng &r, int draw)
{
    Built c;
    double R = r.u(0.6, 1.4), z0 = -R - r.u(0.2, 1), z1 = R + r.u(0.2, 1);
    c.a = cylinder(gp_Pnt(0, 0, z0), gp::DZ(), seam(r, draw, gp::DZ(), gp::DX()), R, z1 - z0);
    c.b = sphere(gp::Origin(), R, sphere_axis(r, draw));
    c.va = v_cyl(R, z1 - z0);
    c.vb = v_sphere(R);
    c.vi = c.vb;
    c.touching = true;
    c.desc = fmt("sphere r %.4f inside a coaxial cylinder of the same radius, tangent along a "
                 "circle (A - B: a void touching the wall)",
                 R);
    return c;
}

Built cyl_through_sphere(Rng &r, int draw)
{
    Built c;
    double rs = r.u(0.8, 1.5), rc = r.u(0.3, 0.8) * rs;
    double z0 = -rs - r.u(0.2, 1), z1 = rs + r.u(0.2, 1);
    c.a = sphere(gp::Origin(), rs, sphere_axis(r, draw));
    c.b = cylinder(gp_Pnt(0, 0, z0), gp::DZ(), seam(r, draw, gp::DZ(), gp::DX()), rc, z1 - z0);
    c.va = v_sphere(rs);
    c.vb = v_cyl(rc, z1 - z0);
    c.vi = 4 * PI / 3 * (rs * rs * rs - std::pow(rs * rs - rc * rc, 1.5));
    c.desc = fmt("cylinder r %.4f through a sphere r %.4f coaxially: sphere minus napkin ring",
                 rc, rs);
    return c;
}

Built cone_apex_in(Rng &r, int)
{
    Built c;
    double R = r.u(0.7, 1.4), H = r.u(1.2, 2.4), h = r.u(0.2, 0.8) * H;
    double x0 = -R - r.u(0.2, 0.8), x1 = R + r.u(0.2, 0.8), y0 = -R - r.u(0.2, 0.8),
           y1 = R + r.u(0.2, 0.8), z1 = H + r.u(0.2, 0.8);
    double rho = R * (H - h) / H;
    c.a = cone(gp::Origin(), R, H);
    c.b = box(x0, y0, h, x1 - x0, y1 - y0, z1 - h);
    c.va = v_cone(R, H);
    c.vb = (x1 - x0) * (y1 - y0) * (z1 - h);
    c.vi = v_cone(rho, H - h);
    c.desc = fmt("cone R %.4f H %.4f, box above z = %.4f: apex inside the box", R, H, h);
    return c;
}

Built cone_apex_out(Rng &r, int)
{
    Built c;
    double R = r.u(0.7, 1.4), H = r.u(1.2, 2.4), h = r.u(0.2, 0.8) * H;
    double x0 = -R - r.u(0.2, 0.8), x1 = R + r.u(0.2, 0.8), y0 = -R - r.u(0.2, 0.8),
           y1 = R + r.u(0.2, 0.8), z0 = -r.u(0.2, 0.8);
    double rho = R * (H - h) / H;
    c.a = cone(gp::Origin(), R, H);
    c.b = box(x0, y0, z0, x1 - x0, y1 - y0, h - z0);
    c.va = v_cone(R, H);
    c.vb = (x1 - x0) * (y1 - y0) * (h - z0);
    c.vi = PI * h * (R * R + R * rho + rho * rho) / 3;
    c.desc = fmt("cone R %.4f H %.4f, box below z = %.4f: frustum, apex outside", R, H, h);
    return c;
}

Built cone_sphere(Rng &r, int draw)
{
    Built c;
    double R = r.u(0.7, 1.4), H = r.u(1.2, 2.4), rho = r.u(0.3, 0.9) * H;
    // The sector is the ball's part inside the infinite cone only while the ball does not
    // reach the base plane: rho < H (the slant height sqrt(R^2 + H^2) is larger).
    c.a = cone(gp::Origin(), R, H);
    c.b = sphere(gp_Pnt(0, 0, H), rho, sphere_axis(r, draw));
    c.va = v_cone(R, H);
    c.vb = v_sphere(rho);
    c.vi = 2 * PI * rho * rho * rho * (1 - H / std::sqrt(R * R + H * H)) / 3;
    c.desc = fmt("sphere r %.4f centred at the apex of a cone R %.4f H %.4f: spherical sector",
                 rho, R, H);
    return c;
}

// Torus's own seam direction: on even draws +y, so the meridian seam lies in the plane x = 0.
gp_Dir torus_seam(Rng &r, int draw) { return seam(r, draw, gp::DZ(), gp::DY()); }

Built torus_half(Rng &r, int draw)
{
    Built c;
    double R = r.u(1.1, 1.8), rr = r.u(0.25, 0.6) * R, e = R + rr;
    double x1 = e + r.u(0.2, 0.8), y0 = -e - r.u(0.2, 0.8), y1 = e + r.u(0.2, 0.8),
           z0 = -rr - r.u(0.2, 0.8), z1 = rr + r.u(0.2, 0.8);
    c.a = torus(torus_seam(r, draw), R, rr);
    c.b = box(0, y0, z0, x1, y1 - y0, z1 - z0);
    c.va = v_torus(R, rr);
    c.vb = x1 * (y1 - y0) * (z1 - z0);
    c.vi = c.va / 2;
    c.desc = fmt("torus R %.4f r %.4f cut by a plane through its axis: half%s", R, rr,
                 draw % 2 ? "" : " (a seam meridian in the plane)");
    return c;
}

Built torus_slab(Rng &r, int draw)
{
    Built c;
    double R = r.u(1.1, 1.8), rr = r.u(0.25, 0.6) * R, e = R + rr, h = r.u(-0.7, 0.7) * rr;
    double x0 = -e - r.u(0.2, 0.8), x1 = e + r.u(0.2, 0.8), y0 = -e - r.u(0.2, 0.8),
           y1 = e + r.u(0.2, 0.8), z1 = rr + r.u(0.2, 0.8);
    c.a = torus(torus_seam(r, draw), R, rr);
    c.b = box(x0, y0, h, x1 - x0, y1 - y0, z1 - h);
    c.va = v_torus(R, rr);
    c.vb = (x1 - x0) * (y1 - y0) * (z1 - h);
    c.vi = torus_above(R, rr, h);
    double p[2] = {R, rr};
    c.check = integrate(f_torus_slice, p, std::asin(h / rr), PI / 2);
    c.desc = fmt("torus R %.4f r %.4f, box above z = %.4f (integral of 4 pi R sqrt(r^2 - z^2))",
                 R, rr, h);
    return c;
}

Built torus_cyl(Rng &r, int draw)
{
    Built c;
    double R = r.u(1.1, 1.8), rr = r.u(0.25, 0.6) * R, rho = R + r.u(-0.7, 0.7) * rr;
    double z0 = -rr - r.u(0.2, 0.8), z1 = rr + r.u(0.2, 0.8);
    c.a = torus(torus_seam(r, draw), R, rr);
    c.b = cylinder(gp_Pnt(0, 0, z0), gp::DZ(), seam(r, draw, gp::DZ(), gp::DX()), rho, z1 - z0);
    c.va = v_torus(R, rr);
    c.vb = v_cyl(rho, z1 - z0);
    c.vi = torus_within(R, rr, rho);
    double p[2] = {R, rr};
    c.check = integrate(f_torus_shell, p, -PI / 2, std::asin((rho - R) / rr));
    c.desc = fmt("torus R %.4f r %.4f and a coaxial cylinder r %.4f", R, rr, rho);
    return c;
}

Built ellipsoid_half(Rng &r, int draw)
{
    Built c;
    double a = r.u(0.8, 1.8), b = r.u(0.8, 1.8), cc = r.u(0.8, 1.8);
    double x1 = a + r.u(0.2, 0.8), y0 = -b - r.u(0.2, 0.8), y1 = b + r.u(0.2, 0.8),
           z0 = -cc - r.u(0.2, 0.8), z1 = cc + r.u(0.2, 0.8);
    c.a = ellipsoid(a, b, cc, sphere_axis(r, draw));
    c.b = box(0, y0, z0, x1, y1 - y0, z1 - z0);
    c.va = v_sphere(1) * a * b * cc;
    c.vb = x1 * (y1 - y0) * (z1 - z0);
    c.vi = c.va / 2;
    c.alt_a = sphere(gp::Origin(), 1, gp::DZ());
    c.alt_b = box(0, y0 / b, z0 / cc, x1 / a, (y1 - y0) / b, (z1 - z0) / cc);
    c.alt_scale = a * b * cc;
    c.desc = fmt("ellipsoid %.4f x %.4f x %.4f cut by a principal plane: half", a, b, cc);
    return c;
}

Built ellipsoid_cap(Rng &r, int draw)
{
    Built c;
    double a = r.u(0.8, 1.8), b = r.u(0.8, 1.8), cc = r.u(0.8, 1.8), h = r.u(-0.6, 0.6) * a;
    double x1 = a + r.u(0.2, 0.8), y0 = -b - r.u(0.2, 0.8), y1 = b + r.u(0.2, 0.8),
           z0 = -cc - r.u(0.2, 0.8), z1 = cc + r.u(0.2, 0.8);
    c.a = ellipsoid(a, b, cc, sphere_axis(r, draw));
    c.b = box(h, y0, z0, x1 - h, y1 - y0, z1 - z0);
    c.va = v_sphere(1) * a * b * cc;
    c.vb = (x1 - h) * (y1 - y0) * (z1 - z0);
    c.vi = a * b * cc * sphere_cap(1, h / a);
    c.alt_a = sphere(gp::Origin(), 1, gp::DZ());
    c.alt_b = box(h / a, y0 / b, z0 / cc, (x1 - h) / a, (y1 - y0) / b, (z1 - z0) / cc);
    c.alt_scale = a * b * cc;
    c.desc = fmt("ellipsoid %.4f x %.4f x %.4f, box beyond x = %.4f: scaled sphere cap", a, b,
                 cc, h);
    return c;
}

// A box with a through hole along z, made by OCCT's own Cut.
struct Holed {
    TopoDS_Shape s;
    double a[3], rh, cx, cy, v;
    gp_Dir seam;
};

Holed holed_box(Rng &r)
{
    Holed h;
    for (int i = 0; i < 3; i++)
        h.a[i] = r.u(1.4, 2.4);
    h.rh = r.u(0.2, 0.4) * std::min(h.a[0], h.a[1]);
    h.cx = r.u(h.rh + 0.15, h.a[0] - h.rh - 0.15);
    h.cy = r.u(h.rh + 0.15, h.a[1] - h.rh - 0.15);
    h.seam = random_perp(r, gp::DZ());
    TopoDS_Shape blk = box(0, 0, 0, h.a[0], h.a[1], h.a[2]);
    TopoDS_Shape tool = cylinder(gp_Pnt(h.cx, h.cy, -1), gp::DZ(), h.seam, h.rh, h.a[2] + 2);
    BRepAlgoAPI_Cut cut(blk, tool);
    if (!cut.IsDone() || cut.HasErrors()) {
        std::fprintf(stderr, "occt_corpus: OCCT could not drill the box\n");
        std::exit(1);
    }
    h.s = cut.Shape();
    h.v = h.a[0] * h.a[1] * h.a[2] - v_cyl(h.rh, h.a[2]);
    return h;
}

Built holed_plug(Rng &r, int draw)
{
    Built c;
    Holed h = holed_box(r);
    double z0 = -r.u(0.2, 0.8), z1 = h.a[2] + r.u(0.2, 0.8);
    c.a = h.s;
    c.b = cylinder(gp_Pnt(h.cx, h.cy, z0), gp::DZ(), seam(r, draw, gp::DZ(), h.seam), h.rh, z1 - z0);
    c.va = h.v;
    c.vb = v_cyl(h.rh, z1 - z0);
    c.desc = fmt("box with a through hole r %.4f (OCCT Cut) and a plug of the same radius in it, "
                 "touching along the whole hole%s",
                 h.rh, draw % 2 ? "" : " (seams on one line)");
    return c;
}

Built holed_thin(Rng &r, int draw)
{
    Built c;
    Holed h = holed_box(r);
    double rp = r.u(0.35, 0.85) * h.rh, z0 = -r.u(0.2, 0.8), z1 = h.a[2] + r.u(0.2, 0.8);
    c.a = h.s;
    c.b = cylinder(gp_Pnt(h.cx, h.cy, z0), gp::DZ(), seam(r, draw, gp::DZ(), h.seam), rp, z1 - z0);
    c.va = h.v;
    c.vb = v_cyl(rp, z1 - z0);
    c.desc = fmt("box with a through hole r %.4f and a thinner coaxial cylinder r %.4f (VI = 0)",
                 h.rh, rp);
    return c;
}

Built holed_box_box(Rng &r, int)
{
    Built c;
    Holed h = holed_box(r);
    double xc = h.cx + r.u(-0.7, 0.7) * h.rh, z0 = r.u(0.2, 0.8) * h.a[2];
    double x1 = h.a[0] + r.u(0.2, 0.8), y0 = -r.u(0.2, 0.8), y1 = h.a[1] + r.u(0.2, 0.8),
           z1 = h.a[2] + r.u(0.2, 0.8);
    c.a = h.s;
    c.b = box(xc, y0, z0, x1 - xc, y1 - y0, z1 - z0);
    c.va = h.v;
    c.vb = (x1 - xc) * (y1 - y0) * (z1 - z0);
    c.vi = ((h.a[0] - xc) * h.a[1] - disc_segment(h.rh, xc - h.cx)) * (h.a[2] - z0);
    c.desc = fmt("box with a through hole r %.4f against a box whose side plane cuts the hole",
                 h.rh);
    return c;
}

struct Config {
    const char *name;
    builder build;
};

const Config CONFIGS[] = {
    {"box_overlap", box_overlap},
    {"box_stacked", box_stacked},
    {"box_coplanar", box_coplanar},
    {"box_edge", box_edge},
    {"box_corner", box_corner},
    {"sphere_lens", sphere_lens},
    {"sphere_touch", sphere_touch},
    {"sphere_inside", sphere_inside},
    {"sphere_cap", sphere_cap},
    {"sphere_corner", sphere_corner},
    {"sphere_edge", sphere_edge},
    {"sphere_on_face", sphere_on_face},
    {"cyl_through", cyl_through},
    {"cyl_lengthwise", cyl_lengthwise},
    {"cyl_on_face", cyl_on_face},
    {"cyl_steinmetz", cyl_steinmetz},
    {"cyl_unequal", cyl_unequal},
    {"cyl_parallel", cyl_parallel},
    {"sphere_in_cyl", sphere_in_cyl},
    {"cyl_through_sphere", cyl_through_sphere},
    {"cone_apex_in", cone_apex_in},
    {"cone_apex_out", cone_apex_out},
    {"cone_sphere", cone_sphere},
    {"torus_half", torus_half},
    {"torus_slab", torus_slab},
    {"torus_cyl", torus_cyl},
    {"ellipsoid_half", ellipsoid_half},
    {"ellipsoid_cap", ellipsoid_cap},
    {"holed_plug", holed_plug},
    {"holed_thin", holed_thin},
    {"holed_box", holed_box_box},
};
const int N_CONFIGS = (int)(sizeof CONFIGS / sizeof CONFIGS[0]);

const char *const POSES[3] = {"axis", "translated", "rotated"};

// ---------------------------------------------------------------- motions and output --------
struct Motion {
    double q[4] = {0, 0, 0, 1}; // x, y, z, w
    double t[3] = {0, 0, 0};
};

Motion random_motion(Rng &r, int pose)
{
    Motion m;
    if (pose == 0)
        return m;
    for (int i = 0; i < 3; i++)
        m.t[i] = r.u(-6, 6);
    if (pose == 2) { // Shoemake: uniform on the unit quaternions
        double u1 = r.u01(), u2 = r.u01(), u3 = r.u01();
        m.q[0] = std::sqrt(1 - u1) * std::sin(2 * PI * u2);
        m.q[1] = std::sqrt(1 - u1) * std::cos(2 * PI * u2);
        m.q[2] = std::sqrt(u1) * std::sin(2 * PI * u3);
        m.q[3] = std::sqrt(u1) * std::cos(2 * PI * u3);
    }
    return m;
}

TopoDS_Shape moved(const TopoDS_Shape &s, const Motion &m, bool nurbs, int pose)
{
    TopoDS_Shape out = s;
    if (pose != 0) {
        gp_Trsf tr;
        tr.SetRotation(gp_Quaternion(m.q[0], m.q[1], m.q[2], m.q[3]));
        gp_Trsf tt;
        tt.SetTranslation(gp_Vec(m.t[0], m.t[1], m.t[2]));
        // Copy: the geometry itself is moved, so the file holds no placement of the shape.
        out = BRepBuilderAPI_Transform(s, tt * tr, Standard_True).Shape();
    }
    if (nurbs)
        out = BRepBuilderAPI_NurbsConvert(out, Standard_True).Shape();
    return out;
}

bool write_step(const TopoDS_Shape &s, const std::string &dir, const std::string &name)
{
    STEPControl_Writer w;
    // The product's name (by default a count of the shapes this process wrote) and the header's
    // time stamp fixed, so that a seed gives the same bytes whatever else is written.
    Interface_Static::SetCVal("write.step.product.name", name.c_str());
    if (w.Transfer(s, STEPControl_AsIs) != IFSelect_RetDone)
        return false;
    APIHeaderSection_MakeHeader header(w.Model());
    header.SetTimeStamp(new TCollection_HAsciiString("2026-01-01T00:00:00"));
    std::string path = dir + "/" + name;
    if (w.Write(path.c_str()) != IFSelect_RetDone)
        return false;
    // The writer still appends its count of the shapes written so far to the product's name
    // ("NAME 41"): drop it, so that a case's file does not depend on the cases before it.
    FILE *f = std::fopen(path.c_str(), "rb");
    if (!f)
        return false;
    std::string text;
    char buf[65536];
    size_t got;
    while ((got = std::fread(buf, 1, sizeof buf, f)) > 0)
        text.append(buf, got);
    std::fclose(f);
    std::string key = "'" + name + " ";
    for (size_t at = text.find(key); at != std::string::npos; at = text.find(key, at + 1)) {
        size_t d = at + key.size(), e = d;
        while (e < text.size() && std::isdigit((unsigned char)text[e]))
            e++;
        if (e > d && e < text.size() && text[e] == '\'')
            text.erase(at + key.size() - 1, e - d + 1);
    }
    f = std::fopen(path.c_str(), "wb");
    if (!f)
        return false;
    bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    return std::fclose(f) == 0 && ok;
}

// Gauss-Kronrod (VolumePropertiesGK): the adaptive VolumeProperties used by occt_bool is off by
// up to a few 1e-7 on OCCT's own rational spheres at eps 1e-9 (1.5e-8 at 1e-10); GK at 1e-12
// is within 1e-14 there.
double occt_volume(const TopoDS_Shape &s)
{
    GProp_GProps p;
    BRepGProp::VolumePropertiesGK(s, p, 1e-12);
    return p.Mass();
}

// The rule occt_bool uses, to measure its own error on the operands.
double occt_volume_bench(const TopoDS_Shape &s)
{
    GProp_GProps p;
    BRepGProp::VolumeProperties(s, p, 1e-9, Standard_False);
    return p.Mass();
}

// |v - ref| relative to |ref|, or to the operands' volumes where the reference is 0.
double disagreement(double v, double ref, double scale)
{
    return std::fabs(v - ref) / (ref != 0 ? std::fabs(ref) : scale);
}

struct Verify {
    double vi = 0, vab = 0, quad = 0, bench = 0;
    int n = 0;
    bool has_quad = false, has_alt = false;
    double alt = 0;
    std::string note;
};

} // namespace

int main(int argc, char **argv)
{
    const char *outdir = nullptr, *only = nullptr;
    uint64_t seed = 1;
    int per = 4;
    bool subset = false, verify = false;
    for (int k = 1; k < argc; k++) {
        if (!std::strcmp(argv[k], "--seed") && k + 1 < argc)
            seed = std::strtoull(argv[++k], nullptr, 10);
        else if (!std::strcmp(argv[k], "--n-per-config") && k + 1 < argc)
            per = std::atoi(argv[++k]);
        else if (!std::strcmp(argv[k], "--only") && k + 1 < argc)
            only = argv[++k];
        else if (!std::strcmp(argv[k], "--subset"))
            subset = true;
        else if (!std::strcmp(argv[k], "--verify"))
            verify = true;
        else if ((argv[k][0] != '-' || !std::strcmp(argv[k], "-")) && !outdir)
            outdir = argv[k];
        else {
            std::fprintf(stderr, "usage: occt_corpus OUTDIR|- [--seed S] [--n-per-config K] "
                                 "[--subset] [--verify] [--only SUBSTR]\n");
            return 2;
        }
    }
    if (!outdir || per < 1) {
        std::fprintf(stderr, "usage: occt_corpus OUTDIR|- [--seed S] [--n-per-config K] "
                             "[--subset] [--verify] [--only SUBSTR]\n");
        return 2;
    }
    if (subset)
        per = 1;
    bool write = std::strcmp(outdir, "-") != 0;
    // OCCT's STEP writer reports its statistics on stdout; the corpus's own output is enough.
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    FILE *json = nullptr;
    if (write) {
        std::string jp = std::string(outdir) + "/cases.json";
        if (!(json = std::fopen(jp.c_str(), "w"))) {
            std::fprintf(stderr, "occt_corpus: cannot write %s\n", jp.c_str());
            return 1;
        }
        std::fprintf(json, "[\n");
    }
    int written = 0, bad = 0;
    std::vector<Verify> ver(N_CONFIGS);
    for (int ci = 0; ci < N_CONFIGS; ci++) {
        const Config &cfg = CONFIGS[ci];
        if (only && !std::strstr(cfg.name, only))
            continue;
        for (int draw = 0; draw < per; draw++) {
            Rng r = rng_for(seed, cfg.name, draw, -1);
            Built b = cfg.build(r, draw);
            double scale = b.va + b.vb;
            if (std::isfinite(b.check)) {
                double q = disagreement(b.vi, b.check, scale);
                ver[ci].quad = std::max(ver[ci].quad, q);
                ver[ci].has_quad = true;
                if (q > 1e-12) {
                    std::fprintf(stderr, "%s draw %d: closed form %.17g, quadrature %.17g\n",
                                 cfg.name, draw, b.vi, b.check);
                    bad = 1;
                }
            }
            if (verify) {
                // OCCT's own intersection of the axis-aligned analytic operands.
                BRepAlgoAPI_Common com(b.a, b.b);
                Verify &v = ver[ci];
                if (!com.IsDone() || com.HasErrors()) {
                    v.note = "OCCT Common failed";
                } else {
                    double vi = occt_volume(com.Shape());
                    double e = disagreement(vi, b.vi, scale);
                    if (e > 1e-6)
                        std::fprintf(stderr, "%s draw %d: V(A n B) formula %.12g, OCCT %.12g\n",
                                     cfg.name, draw, b.vi, vi);
                    v.vi = std::max(v.vi, e);
                }
                if (std::isfinite(b.alt_scale)) {
                    BRepAlgoAPI_Common alt(b.alt_a, b.alt_b);
                    if (alt.IsDone() && !alt.HasErrors())
                        v.alt = std::max(v.alt, disagreement(b.alt_scale * occt_volume(alt.Shape()),
                                                             b.vi, scale));
                    v.has_alt = true;
                }
                v.n++;
            }
            for (int pose = 0; pose < 3; pose++) {
                Rng rm = rng_for(seed, cfg.name, draw, pose);
                Motion m = random_motion(rm, pose);
                for (int nurbs = 0; nurbs < 2; nurbs++) {
                    // The committed subset: every pose and both face kinds of each
                    // configuration, in 4 of the 6 combinations (which 2 are left out turns
                    // with the configuration's index).
                    if (subset && ((pose == ci % 3 && !nurbs) || (pose == (ci + 1) % 3 && nurbs)))
                        continue;
                    char id[128];
                    std::snprintf(id, sizeof id, "%s_%d_%s_%s", cfg.name, draw, POSES[pose],
                                  nurbs ? "nurbs" : "analytic");
                    TopoDS_Shape sa = moved(b.a, m, nurbs, pose), sb = moved(b.b, m, nurbs, pose);
                    if (verify) {
                        double ea = disagreement(occt_volume(sa), b.va, b.va);
                        double eb = disagreement(occt_volume(sb), b.vb, b.vb);
                        ver[ci].vab = std::max(ver[ci].vab, std::max(ea, eb));
                        ea = disagreement(occt_volume_bench(sa), b.va, b.va);
                        eb = disagreement(occt_volume_bench(sb), b.vb, b.vb);
                        ver[ci].bench = std::max(ver[ci].bench, std::max(ea, eb));
                    }
                    if (!write)
                        continue;
                    std::string pa = std::string(id) + "_a.step", pb = std::string(id) + "_b.step";
                    if (!write_step(sa, outdir, pa) || !write_step(sb, outdir, pb)) {
                        std::fprintf(stderr, "occt_corpus: %s: the STEP writer failed\n", id);
                        bad = 1;
                        continue;
                    }
                    std::fprintf(json,
                                 "%s{\"id\": \"%s\", \"config\": \"%s\", \"draw\": %d, \"pose\": "
                                 "\"%s\", \"faces\": \"%s\", \"a\": \"%s\", \"b\": \"%s\", "
                                 "\"motion\": {\"quaternion\": [%.17g, %.17g, %.17g, %.17g], "
                                 "\"translation\": [%.17g, %.17g, %.17g]}, \"va\": %.17g, "
                                 "\"vb\": %.17g, \"vi\": %.17g, \"union\": %.17g, "
                                 "\"intersection\": %.17g, \"difference\": %.17g, "
                                 "\"touching\": %s, \"description\": \"%s\"}",
                                 written ? ",\n" : "", id, cfg.name, draw, POSES[pose],
                                 nurbs ? "nurbs" : "analytic", pa.c_str(), pb.c_str(), m.q[0],
                                 m.q[1], m.q[2], m.q[3], m.t[0], m.t[1], m.t[2], b.va, b.vb, b.vi,
                                 b.va + b.vb - b.vi, b.vi, b.va - b.vi,
                                 b.touching ? "true" : "false", b.desc.c_str());
                    written++;
                }
            }
        }
    }
    if (json) {
        std::fprintf(json, "\n]\n");
        std::fclose(json);
        std::printf("occt_corpus: %d cases written to %s (seed %llu)\n", written, outdir,
                    (unsigned long long)seed);
    }
    std::printf("%-20s %6s %12s %12s %12s %12s %12s\n", "configuration", "draws", "VI vs OCCT",
                "VA,VB vs OCCT", "VI vs quad.", "VA,VB 1e-9", "VI vs scaled");
    for (int ci = 0; ci < N_CONFIGS; ci++) {
        if (only && !std::strstr(CONFIGS[ci].name, only))
            continue;
        const Verify &v = ver[ci];
        char quad[32] = "-";
        if (v.has_quad)
            std::snprintf(quad, sizeof quad, "%.2e", v.quad);
        if (verify)
        {
            char alt[32] = "-";
            if (v.has_alt)
                std::snprintf(alt, sizeof alt, "%.2e", v.alt);
            std::printf("%-20s %6d %12.2e %12.2e %12s %12.2e %12s  %s\n", CONFIGS[ci].name, v.n,
                        v.vi, v.vab, quad, v.bench, alt, v.note.c_str());
        }
        else if (v.has_quad)
            std::printf("%-20s %6d %12s %12s %12s\n", CONFIGS[ci].name, per, "-", "-", quad);
    }
    return bad;
}
