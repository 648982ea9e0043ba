/* The shipped Boolean scenarios (cb_model_scenario: the two hummingbirds, the Cardan-joint
 * scenarios analytic and B-spline, the bracket), Colibri beside Open CASCADE; bench_bool_driver.h
 * says what is measured and how. Usage: bench_scenarios [RUNS [OCCT_BOOL [JSON_OUT]]]. */
#define _DEFAULT_SOURCE /* wait4: the rusage of one child, not of all of them */
#include "bench/bench_bool_driver.h"

/* Scenario k with its references and bars. */
static cb_status build_case(bench_bool_case *c, int k, const char *shared, cb_error *err)
{
    (void)shared;
    return bench_bool_scenario_case(c, k, err);
}

int main(int argc, char **argv)
{
    const bench_bool_suite suite = {"bench_scenarios", "Booleans on the shipped scenarios",
                                    cb_model_scenario_count(), build_case};
    return bench_bool_main(&suite, argc, argv);
}
