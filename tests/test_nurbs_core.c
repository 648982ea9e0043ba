#include "brep/nurbs.h"
#include "check.h"

int main(void)
{
    cb_nurbs_curve_t c;
    cb_nurbs_curve_init(c);
    double U[] = {0, 0, 0, 1, 1, 1};
    double P[] = {0, 0, 0, 1, 1, 0, 2, 0, 0};
    cb_error err;
    CHECK(cb_nurbs_curve_make(c, 2, U, 6, P, NULL, 3, &err) == CB_OK, "%s", err.msg);
    double p[3];
    cb_nurbs_curve_eval(p, c, 0.5);
    CHECK(p[0] == 1.0 && p[1] == 0.5, "%g %g", p[0], p[1]);
    cb_nurbs_curve_clear(c);
    return check_report("nurbs_core");
}
