#!/usr/bin/env python3
"""Rewrites a STEP file written in radians as a writer measuring plane angles in degrees does:
the context's PLANE_ANGLE_UNIT becomes a CONVERSION_BASED_UNIT 'DEGREE', cone semi-angles are
written in degrees, and so are the angle coordinates of the pcurves (2D lines and B-splines) on
cylinders and cones (u) and on spheres and tori (u and v), as ISO 10303-42 measures those
parameters in the context's angle unit. The pcurves keep their own parameter. Only the
entities it needs are understood; it fails on anything else in a pcurve.

usage: to_degrees.py IN.step OUT.step"""
import math
import re
import sys

K = 180.0 / math.pi
src = open(sys.argv[1]).read()
head, data = src.split("DATA;", 1)
body, tail = data.rsplit("ENDSEC;", 1)
rec = {int(m.group(1)): " ".join(m.group(2).split())
       for m in re.finditer(r"#(\d+)\s*=\s*(.*?);\s*(?=#\d+\s*=|$)", body, re.S)}
next_id = max(rec) + 1


def new(text):
    global next_id
    rec[next_id] = text
    next_id += 1
    return next_id - 1


def num(x):
    return repr(float(x))


def refs(text):
    return [int(r) for r in re.findall(r"#(\d+)", text)]


def point2(i, k):
    a, b = re.search(r"\(\s*([-\d.E+]+)\s*,\s*([-\d.E+]+)\s*\)", rec[i]).groups()
    return new("CARTESIAN_POINT('',(%s,%s))" % (num(float(a) * k[0]), num(float(b) * k[1])))


def scale_curve(c, k):
    t = rec[c]
    if t.startswith("LINE("):
        p, v = refs(t)
        d, m = re.match(r"VECTOR\('[^']*',#(\d+),\s*([-\d.E+]+)\)", rec[v]).groups()
        dx, dy = map(float, re.search(r"\(\s*([-\d.E+]+)\s*,\s*([-\d.E+]+)\s*\)",
                                      rec[int(d)]).groups())
        vx, vy = dx * float(m) * k[0], dy * float(m) * k[1]
        n = math.hypot(vx, vy)
        nd = new("DIRECTION('',(%s,%s))" % (num(vx / n), num(vy / n)))
        return new("LINE('',#%d,#%d)" % (point2(p, k), new("VECTOR('',#%d,%s)" % (nd, num(n)))))
    if t.startswith("B_SPLINE_CURVE_WITH_KNOTS("):
        pts = re.search(r"\(\s*(#\d+(?:\s*,\s*#\d+)*)\s*\)", t).group(1)
        new_pts = ",".join("#%d" % point2(p, k) for p in refs(pts))
        return new(t.replace(pts, new_pts, 1))
    sys.exit("to_degrees: pcurve #%d: %s not handled" % (c, t[:40]))


SCALE = {"CYLINDRICAL_SURFACE": (K, 1.0), "CONICAL_SURFACE": (K, 1.0),
         "SPHERICAL_SURFACE": (K, K), "TOROIDAL_SURFACE": (K, K)}
for i in sorted(rec):
    t = rec[i]
    if t.startswith("PCURVE("):
        s, d = refs(t)
        k = SCALE.get(rec[s].split("(")[0].strip())
        if not k:
            continue
        c, ctx = refs(rec[d])
        rec[d] = "DEFINITIONAL_REPRESENTATION('',(#%d),#%d)" % (scale_curve(c, k), ctx)
    elif t.startswith("CONICAL_SURFACE("):
        m = re.match(r"(CONICAL_SURFACE\('[^']*',#\d+,[-\d.E+]+,)([-\d.E+]+)\)", t)
        rec[i] = m.group(1) + num(float(m.group(2)) * K) + ")"
for i in sorted(rec):
    if "PLANE_ANGLE_UNIT" in rec[i] and "RADIAN" in rec[i]:
        rad = new(rec[i])
        meas = new("PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(%s),#%d)"
                   % (num(math.pi / 180), rad))
        dims = new("DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.)")
        rec[i] = "( CONVERSION_BASED_UNIT('DEGREE',#%d) NAMED_UNIT(#%d) PLANE_ANGLE_UNIT() )" % (
            meas, dims)
        break
with open(sys.argv[2], "w") as out:
    out.write(head + "DATA;\n")
    for i in sorted(rec):
        out.write("#%d = %s;\n" % (i, rec[i]))
    out.write("ENDSEC;" + tail)
