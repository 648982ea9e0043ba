/* The shipped Boolean scenarios (cb_model_scenario: the two hummingbirds, the Cardan-joint
 * scenarios analytic and B-spline, the bracket), Colibri beside Open CASCADE; bench_bool_driver.h
 * says what is measured and how. Usage: bench_scenarios [RUNS [OCCT_BOOL [JSON_OUT]]]. */
#define _DEFAULT_SOURCE /* wait4: the rusage of one child, not of all of them */
#include <stdio.h>
#include <string.h>

#include "bench/bench_bool_driver.h"
#include "models/models.h"

/* Scenario k with its references and bars; its operands move into c. */
static cb_status build_case(bench_bool_case *c, int k, const char *shared, cb_error *err)
{
    (void)shared;
    cb_model_scenario s;
    cb_status st = cb_model_scenario_load(&s, k, err);
    if (st)
        return st;
    snprintf(c->name, sizeof c->name, "%s", s.name);
    c->a = s.a;
    c->b = s.b;
    memcpy(c->ref, s.ref, sizeof c->ref);
    memcpy(c->bar, s.bar, sizeof c->bar);
    return CB_OK;
}

int main(int argc, char **argv)
{
    const bench_bool_suite suite = {"bench_scenarios", "Booleans on the shipped scenarios",
                                    cb_model_scenario_count(), build_case};
    return bench_bool_main(&suite, argc, argv);
}
