/* The colibri command: exit codes and messages of every command (binary from COLIBRI_BINARY).
 * Exit status: 0 success, 1 a negative verdict (invalid model, failed check), 2 bad usage or an
 * input that cannot be used. Also: `colibri info`'s volume and area against Open CASCADE's
 * figures; `colibri model cardan`'s files read back against the closed-form volumes and its
 * reference table against models/reference.json; the --quiet and --threads flags of ssi, and
 * its --svg pictures against its --json output. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brep/mass.h"
#include "check.h"
#include "check_cli.h"
#include "io/step.h"
#include "models/models.h"

/* The number after "key": in the output of the last run (NaN if absent). */
static double json_number(const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *at = strstr(cli_out, pat);
    return at ? strtod(at + strlen(pat), NULL) : NAN;
}

/* The whole of a file, NUL-terminated (NULL if it cannot be read); *size its length. */
static char *slurp_size(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *text = NULL;
    size_t len = 0, cap = 0, got;
    char chunk[4096];
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (len + got + 1 > cap) {
            cap = 2 * (len + got + 1);
            text = realloc(text, cap);
        }
        memcpy(text + len, chunk, got);
        len += got;
    }
    fclose(f);
    if (text)
        text[len] = '\0';
    *size = len;
    return text;
}

static char *slurp(const char *path)
{
    size_t size;
    return slurp_size(path, &size);
}

/* text with the first `from` replaced by `to`, in a new string (NULL if from is missing). */
static char *replaced(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    CHECK(at != NULL, "test setup: '%s' not in the model", from);
    if (!at)
        return NULL;
    size_t head = (size_t)(at - text);
    char *out = malloc(strlen(text) - strlen(from) + strlen(to) + 1);
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + strlen(from));
    return out;
}

static void write_file(const char *path, const char *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL, "cannot write %s", path);
    if (!f)
        return;
    fwrite(data, 1, len, f);
    fclose(f);
}

/* `colibri info` on `text` with the first `from` replaced by `to`, written to path: exit code
 * `code` and a message holding `want` (where "@" stands for the path). */
static void info_corrupted(const char *path, const char *text, const char *from, const char *to,
                           int code, const char *want)
{
    char *out = replaced(text, from, to);
    if (!out)
        return;
    write_file(path, out, strlen(out));
    free(out);
    char args[1200], msg[1200];
    snprintf(args, sizeof args, "info %s", path);
    const char *mark = strchr(want, '@');
    if (mark)
        snprintf(msg, sizeof msg, "%.*s%s%s", (int)(mark - want), want, path, mark + 1);
    else
        snprintf(msg, sizeof msg, "%s", want);
    cli_expect(args, code, msg);
}

/* Every class of unusable STEP input gives exit 2 and a message naming file:line and #id;
 * a model that reads but fails validation gives 1. The corruptions are made on
 * ujoint_cross.step, whose lines 33-39 read
 *   #21 = EDGE_CURVE('',#22,#24,#26,.T.);
 *   #22 = VERTEX_POINT('',#23);
 *   #23 = CARTESIAN_POINT('',(85.,100.,0.));
 *   ...
 *   #27 = LINE('',#28,#29); */
static void test_bad_step(const char *sh)
{
    char model[1024], path[128], args[1200];
    snprintf(model, sizeof model, "%s/models/ujoint_cross.step", sh);
    char *text = slurp(model);
    CHECK(text != NULL, "cannot read %s", model);
    if (!text)
        return;
    snprintf(path, sizeof path, "/tmp/colibri_cli_step_%ld.step", (long)getpid());
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#99999);",
                   2, "@:34: #22 VERTEX_POINT: vertex_geometry: #99999 is not defined");
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#23)", 2,
                   "@:35: #22 VERTEX_POINT: expected ';'");
    info_corrupted(path, text, "#27 = LINE('',#28,#29);",
                   "#27 = SURFACE_CURVE('',#27,(),.CURVE_3D.);", 2,
                   "@:39: #27 SURFACE_CURVE: cyclic reference");
    info_corrupted(path, text, "#27 = LINE('',#28,#29);", "#27 = LINE('',#28);", 2,
                   "@:39: #27 LINE: 2 parameters given, 3 expected");
    info_corrupted(path, text, "#21 = EDGE_CURVE('',#22,#24,#26,.T.);",
                   "#21 = EDGE_CURVE('',#22,#24,#26,1.5);", 2,
                   "@:33: #21 EDGE_CURVE: same_sense: .T. or .F. expected, found a real");
    info_corrupted(path, text, "#22 = VERTEX_POINT('',#23);", "#22 = VERTEX_POINT('',#22);", 2,
                   "@:34: #22 VERTEX_POINT: CARTESIAN_POINT expected");
    info_corrupted(path, text, "(85.,100.,0.)", "(1e300,100.,0.)", 2,
                   "@:35: #23 CARTESIAN_POINT: coordinate 1 is 1e+300, beyond");
    info_corrupted(path, text, "(85.,100.,0.)", "(1e999,100.,0.)", 2,
                   "@:35: #23 CARTESIAN_POINT: number 1e999 is not a finite double");
    /* Truncated inside an entity: the instance cut is named, at its line. */
    const char *cut = strstr(text, "#185 = B_SPLINE_CURVE_WITH_KNOTS(");
    CHECK(cut != NULL, "test setup: #185 not in the model");
    if (cut) {
        int line = 1;
        for (const char *c = text; c < cut; c++)
            line += *c == '\n';
        write_file(path, text, (size_t)(cut - text) + 60);
        snprintf(args, sizeof args, "info %s", path);
        char want[256];
        snprintf(want, sizeof want, "%s:%d: #185 B_SPLINE_CURVE_WITH_KNOTS: ", path, line);
        cli_expect(args, 2, want);
    }
    /* Empty file, binary garbage. */
    write_file(path, "", 0);
    snprintf(args, sizeof args, "info %s", path);
    cli_expect(args, 2, "empty file");
    char garbage[256];
    for (int k = 0; k < 256; k++)
        garbage[k] = (char)(k * 37 + 11);
    write_file(path, garbage, sizeof garbage);
    char want[256];
    snprintf(want, sizeof want, "%s:1: not a STEP file", path);
    cli_expect(args, 2, want);
    /* Read, but invalid: vertex #23 moved by 1 (far beyond the 0.0117 cap on edge
     * tolerances) leaves the edges at it off their vertex. */
    info_corrupted(path, text, "(85.,100.,0.)", "(85.,100.,1.)", 1,
                   "edge 2: curve start is 0.707 from vertex 0");
    cli_expect(args, 1, "4 edges deviate beyond the cap");
    snprintf(args, sizeof args, "info %s --json", path);
    cli_expect(args, 1, "\"valid\": false");
    cli_expect(args, 1, "\"edges_over_cap\": 4");
    /* Its loops no longer close: no volume, and no crash. */
    cli_expect(args, 1, "\"volume\": null, \"area\": null, \"mass_error\": \"mass: face 0: ");
    remove(path);
    free(text);
}

/* check and ssi: unusable files give 2, a failed check 1. */
static void test_other_commands(const char *sh)
{
    char path[128], args[1200];
    snprintf(path, sizeof path, "/tmp/colibri_cli_mesh_%ld.off", (long)getpid());
    const char *tri = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    write_file(path, tri, strlen(tri));
    snprintf(args, sizeof args, "check %s", path);
    cli_expect(args, 1, "closed: no (3 boundary edges)");
    write_file(path, "OFF\nabc def\n", 12);
    cli_expect(args, 2, path);
    remove(path);
    cli_expect("check /nonexistent/x.stl", 2, "x.stl: cannot open");
    snprintf(args, sizeof args, "check '%s/models/SOURCES.md'", sh);
    cli_expect(args, 2, "unknown mesh format");
    cli_expect("check", 2, "usage: colibri check");
    snprintf(args, sizeof args, "ssi /nonexistent/a.step '%s/models/ujoint_cross.step'", sh);
    cli_expect(args, 2, "a.step: cannot open");
    cli_expect("ssi a.step", 2, "two STEP files are needed");
    cli_expect("model hummingbird -o /nonexistent/dir/bird.step", 2, "bird.step");
    cli_expect("model sparrow -o x.step", 2, "unknown model 'sparrow'");
}

/* `colibri info`'s volume and area: the fork against Open CASCADE's figures (models/SOURCES.md,
 * to 1e-6), the unit named from the file's, and an open shell or a patch file told gracefully. */
static void test_info_mass(const char *sh)
{
    char args[1200], path[128];
    snprintf(args, sizeof args, "info --json '%s/models/ujoint_fork.step'", sh);
    cli_expect(args, 0, "\"mass_error\": null}");
    double v = json_number("volume"), a = json_number("area");
    CHECK(fabs(v - 81046.104) <= 1e-6 * 81046.104 && fabs(a - 23955.819) <= 1e-6 * 23955.819,
          "ujoint_fork: volume %.10g (OCCT 81046.104), area %.10g (OCCT 23955.819)", v, a);
    snprintf(args, sizeof args, "info '%s/models/ujoint_fork.step'", sh);
    cli_expect(args, 0, "volume 81046.10");
    const char *line = strstr(cli_out, "volume 81046.10");
    double tv = line ? strtod(line + 7, NULL) : NAN;
    CHECK(line && strstr(line, " mm^3, area 23955.8") && strstr(line, " mm^2\n") &&
              fabs(tv - v) <= 1e-9 * v,
          "ujoint_fork: text volume line:\n%s", cli_out);
    char model[1024];
    snprintf(model, sizeof model, "%s/models/ujoint_cross.step", sh);
    char *text = slurp(model);
    CHECK(text != NULL, "cannot read %s", model);
    if (!text)
        return;
    snprintf(path, sizeof path, "/tmp/colibri_cli_mass_%ld.step", (long)getpid());
    snprintf(args, sizeof args, "info %s", path);
    /* The same cross in centimetres: the unit follows the file's. */
    char *cm = replaced(text, "SI_UNIT(.MILLI.,.METRE.)", "SI_UNIT(.CENTI.,.METRE.)");
    if (cm) {
        write_file(path, cm, strlen(cm));
        cli_expect(args, 0, "volume 95097.33");
        CHECK(strstr(cli_out, " cm^3, area 14307.07") && strstr(cli_out, " cm^2\n"),
              "centimetre cross:\n%s", cli_out);
    }
    free(cm);
    /* A sheet beside the solid (a surface model's open shell of one of its faces): the volume
     * is the solid's, the area adds the sheet's. */
    char *sheet = replaced(text, "ENDSEC;\nEND-ISO-10303-21;",
                           "#900001 = OPEN_SHELL('',(#17));\n"
                           "#900002 = SHELL_BASED_SURFACE_MODEL('',(#900001));\n"
                           "ENDSEC;\nEND-ISO-10303-21;");
    if (sheet) {
        write_file(path, sheet, strlen(sheet));
        snprintf(args, sizeof args, "info %s --json", path);
        cli_expect(args, 0, "\"mass_error\": null}");
        double sv = json_number("volume"), sa = json_number("area");
        CHECK(fabs(sv - 95097.33) < 0.01 && sa > 14307.08 && sa < 2 * 14307.07,
              "cross with a sheet: volume %.10g (95097.33), area %.10g (above 14307.07)", sv, sa);
        snprintf(args, sizeof args, "info %s", path);
    }
    free(sheet);
    /* An open shell of a surface model: valid, it bounds no volume, its area is the faces';
     * with the cross's last face in a surface model of its own, the two areas add up to the
     * closed cross's. */
    char *sbsm = replaced(text, "#15 = MANIFOLD_SOLID_BREP('',#16);",
                          "#15 = SHELL_BASED_SURFACE_MODEL('',(#16));");
    double parts = 0;
    for (int k = 0; k < 2 && sbsm; k++) {
        char *open_shell =
            replaced(sbsm, "#16 = CLOSED_SHELL('',(#17,#230,#339,#443,#447,#503,#507,#511));",
                     k ? "#16 = OPEN_SHELL('',(#511));"
                       : "#16 = OPEN_SHELL('',(#17,#230,#339,#443,#447,#503,#507));");
        if (!open_shell)
            break;
        write_file(path, open_shell, strlen(open_shell));
        snprintf(args, sizeof args, "info %s", path);
        cli_expect(args, 0, "volume: none (a surface model: open shells), area ");
        snprintf(args, sizeof args, "info %s --json", path);
        cli_expect(args, 0, "\"volume\": null, \"area\": ");
        CHECK(cli_out[0] == '{' && strchr(cli_out, '\n') == cli_out + strlen(cli_out) - 1 &&
                  strstr(cli_out, "\"mass_error\": null}"),
              "open shell: not one JSON line without an error:\n%s", cli_out);
        double a = json_number("area");
        CHECK(a > 0 && a < 14307.07, "open shell %d: area %.10g", k, a);
        parts += a;
        free(open_shell);
    }
    CHECK(fabs(parts - 14307.078) < 0.01, "open shells: areas add up to %.10g, not 14307.078",
          parts);
    free(sbsm);
    free(text);
    remove(path);
    /* A patch file has no volume to give, and says nothing of one. */
    snprintf(args, sizeof args, "info --json '%s/models/teapot.bpt'", sh);
    cli_expect(args, 0, "\"format\": \"bpt\", \"patches\": 32");
    CHECK(!strstr(cli_out, "volume") && !strstr(cli_out, "mass"), "teapot:\n%s", cli_out);
}

/* The number after `label` in the output of the last run (NaN if absent). */
static double number_after(const char *label)
{
    const char *at = strstr(cli_out, label);
    return at ? strtod(at + strlen(label), NULL) : NAN;
}

/* A STEP file written by `colibri model cardan`, read back: one solid of the part's faces,
 * whose volume (brep/mass.h) is the closed form within 1e-9. */
static void check_cardan_file(const char *path, const cb_cardan_params *p, const char *what)
{
    int faces = p->kind == CB_CARDAN_CROSS ? 14 : p->yoke.fillet_radius > 0 ? 16 : 14;
    double ref = NAN;
    cb_error err;
    cb_error_clear(&err);
    CHECK(cb_model_cardan_volume(&ref, p, &err) == CB_OK, "%s: %s", what, err.msg);
    cb_topo_body *b = NULL;
    cb_status st = cb_step_read(&b, path, &err);
    CHECK(st == CB_OK, "%s: read back: %s", what, err.msg);
    if (st)
        return;
    CHECK(b->n_solids == 1 && b->n_faces == faces, "%s: %d solids, %d faces, expected 1, %d",
          what, b->n_solids, b->n_faces, faces);
    const char *names[8];
    int counts[8], nt = cb_topo_body_surface_types(names, counts, b);
    int bspline = nt > 0 && !strcmp(names[0], "bspline") ? counts[0] : 0;
    CHECK(bspline == (p->as_nurbs ? faces : 0), "%s: %d B-spline faces", what, bspline);
    cb_mass_props m;
    st = cb_mass_body(&m, b, 0, NULL, &err);
    CHECK(st == CB_OK && fabs(m.volume - ref) <= 1e-9 * ref,
          "%s: volume %.15g, closed form %.15g: %s", what, m.volume, ref, st ? err.msg : "");
    cb_topo_body_free(b);
}

/* `colibri model cardan`: parts and scenarios written, read back and measured; the scenario
 * list; the reference table equal to models/reference.json byte for byte; bad use. */
static void test_model_cardan(void)
{
    char a[128], b[128], args[1200];
    snprintf(a, sizeof a, "/tmp/colibri_cli_cardan_%ld_a.step", (long)getpid());
    snprintf(b, sizeof b, "/tmp/colibri_cli_cardan_%ld_b.step", (long)getpid());
    cli_expect("model --help", 0, "colibri model cardan SCENARIO -o A.step --out-b B.step");
    CHECK(strstr(cli_out, "colibri model cardan cross|yoke -o FILE.step") &&
              strstr(cli_out, "colibri model --reference"),
          "model --help:\n%s", cli_out);

    /* Single parts, in several poses, analytic and B-spline. */
    static const struct {
        const char *opts;
        cb_cardan_kind kind;
        int nurbs;
        double fillet; /* < 0: the default */
        cb_model_pose pose;
    } parts[] = {
        {"cross", CB_CARDAN_CROSS, 0, -1, {{0, 0, 1}, 0, {0, 0, 0}}},
        {"yoke", CB_CARDAN_YOKE, 0, -1, {{0, 0, 1}, 0, {0, 0, 0}}},
        {"cross --nurbs --rotate 1 2 3 37 --translate 10 -5 2.5", CB_CARDAN_CROSS, 1, -1,
         {{1, 2, 3}, 37, {10, -5, 2.5}}},
        {"yoke --nurbs --translate 0 0 3 --rotate 1 0 0 60", CB_CARDAN_YOKE, 1, -1,
         {{1, 0, 0}, 60, {0, 0, 3}}},
        {"yoke --fillet 0 --rotate 0 0 1 90", CB_CARDAN_YOKE, 0, 0, {{0, 0, 1}, 90, {0, 0, 0}}},
        {"yoke --fillet 0.25 --nurbs", CB_CARDAN_YOKE, 1, 0.25, {{0, 0, 1}, 0, {0, 0, 0}}},
    };
    for (size_t k = 0; k < sizeof parts / sizeof parts[0]; k++) {
        cb_cardan_params p;
        cb_cardan_params_default(&p, parts[k].kind);
        p.as_nurbs = parts[k].nurbs;
        p.pose = parts[k].pose;
        if (parts[k].fillet >= 0)
            p.yoke.fillet_radius = parts[k].fillet;
        double ref = NAN;
        cb_error err;
        cb_model_cardan_volume(&ref, &p, &err);
        snprintf(args, sizeof args, "model cardan %s -o %s", parts[k].opts, a);
        cli_expect(args, 0, "validation (tolerance ");
        CHECK(strstr(cli_out, "): valid\n") && number_after("volume (closed form): ") == ref,
              "%s: printed volume %.17g, closed form %.17g:\n%s", args,
              number_after("volume (closed form): "), ref, cli_out);
        check_cardan_file(a, &p, args);
    }

    /* Scenarios: both parts, and the six volumes of cb_cardan_scenario_volumes. */
    const char *labels[6] = {"  A      ", "  B      ", "  A u B  ",
                             "  A n B  ", "  A - B  ", "  B - A  "};
    for (int k = 0; k < cb_cardan_scenario_count(); k++) {
        cb_cardan_scenario s;
        cb_cardan_volumes v;
        cb_error err;
        cb_error_clear(&err);
        if (cb_cardan_scenario_get(&s, k, &err) || cb_cardan_scenario_volumes(&v, &s, &err)) {
            CHECK(0, "scenario %d: %s", k, err.msg);
            continue;
        }
        int nurbs = k % 2; /* half of them with B-spline faces */
        s.a.as_nurbs = s.b.as_nurbs = nurbs;
        snprintf(args, sizeof args, "model cardan %s -o %s --out-b %s%s", s.name, a, b,
                 nurbs ? " --nurbs" : "");
        cli_expect(args, 0, s.contact);
        const double want[6] = {v.a, v.b, v.a_union_b, v.a_inter_b, v.a_minus_b, v.b_minus_a};
        for (int i = 0; i < 6; i++)
            CHECK(number_after(labels[i]) == want[i], "%s: %s%.17g printed, closed form %.17g",
                  s.name, labels[i], number_after(labels[i]), want[i]);
        char what[160];
        snprintf(what, sizeof what, "%s A%s", s.name, nurbs ? " (B-spline)" : "");
        check_cardan_file(a, &s.a, what);
        snprintf(what, sizeof what, "%s B%s", s.name, nurbs ? " (B-spline)" : "");
        check_cardan_file(b, &s.b, what);
    }
    cli_expect("model cardan --list", 0, "cross_in_yoke       A yoke, B cross: ");
    int lines = 0;
    for (const char *c = cli_out; *c; c++)
        lines += *c == '\n';
    CHECK(lines == cb_cardan_scenario_count() && strstr(cli_out, "\ncrosses_stacked     A cross"),
          "model cardan --list:\n%s", cli_out);

    /* The reference table, byte for byte the shipped file. */
    const char *src = getenv("COLIBRI_SOURCE");
    char ref_path[1024], out_path[128];
    snprintf(ref_path, sizeof ref_path, "%s/models/reference.json", src ? src : ".");
    snprintf(out_path, sizeof out_path, "/tmp/colibri_cli_reference_%ld.json", (long)getpid());
    snprintf(args, sizeof args, "model --reference > %s", out_path);
    int code = cli_run(args);
    size_t n_ref = 0, n_out = 0;
    char *shipped = slurp_size(ref_path, &n_ref), *printed = slurp_size(out_path, &n_out);
    CHECK(code == 0 && shipped && printed && n_ref == n_out && !memcmp(shipped, printed, n_ref),
          "colibri model --reference (exit %d, %zu bytes) differs from %s (%zu bytes)", code,
          n_out, ref_path, n_ref);
    free(shipped);
    free(printed);
    remove(out_path);
    cli_expect("model cardan --reference", 0, "\"parts\": {\n    \"cross\": {\"half_size\": 1,");

    /* Unknown names list the valid ones; bad numbers, misplaced options, unwritable files. */
    snprintf(args, sizeof args, "model cardan sphere -o %s", a);
    cli_expect(args, 2, "unknown cardan part or scenario 'sphere' (parts: cross, yoke; "
                        "scenarios: cross_in_yoke, cross_on_base, cross_into_base, "
                        "cross_through_yoke, two_crosses, crosses_stacked)");
    cli_expect("model cardan", 2, "parts: cross, yoke; scenarios: cross_in_yoke");
    cli_expect("model cardan yoke", 2, "needs a part or scenario and -o FILE");
    static const struct {
        const char *opts, *message;
    } bad[] = {
        {"cross --rotate 0 0 0 30", "--rotate: bad or missing values"},
        {"cross --rotate 0 0 1", "--rotate: bad or missing values"},
        {"cross --translate 1 2 abc", "--translate: bad or missing values"},
        {"cross --translate 1 2 inf", "--translate: bad or missing values"},
        {"yoke --fillet nan", "--fillet: bad or missing values"},
        {"yoke --fillet 1.5", "fillet radius f 1.5 must be"},
        {"yoke --fillet -0.1", "fillet radius f -0.10000000000000001 must be"},
        {"cross --fillet 0.25", "--fillet does not apply to the cross"},
        {"cross --scale 2", "--scale does not apply to cardan"},
        {"yoke --wing-angle 5", "--wing-angle does not apply to cardan"},
        {"cross --out-b x.step", "--out-b does not apply to a single part"},
        {"cross_into_base", "--out-b FILE is needed for part B"},
        {"cross_into_base --out-b x.step --rotate 0 0 1 10", "--rotate does not apply to a"},
        {"cross_into_base --out-b x.step --translate 0 0 1", "--translate does not apply"},
        {"cross_into_base --out-b x.step --fillet 0", "--fillet does not apply to a scenario"},
        {"cross yoke", "usage: colibri model NAME"},
        {"cross --bogus", "usage: colibri model NAME"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "model cardan %s -o %s", bad[k].opts, a);
        cli_expect(args, 2, bad[k].message);
    }
    cli_expect("model cardan --list two_crosses", 2, "usage: colibri model NAME");
    cli_expect("model --reference -o x.step", 2, "usage: colibri model NAME");
    snprintf(args, sizeof args, "model hummingbird -o %s --nurbs", a);
    cli_expect(args, 2, "--nurbs does not apply to hummingbird");
    cli_expect("model cardan cross -o /nonexistent/dir/cross.step", 2, "cross.step: cannot create");
    snprintf(args, sizeof args, "model cardan two_crosses -o %s --out-b /nonexistent/dir/b.step",
             a);
    cli_expect(args, 2, "b.step: cannot create");
    remove(a);
    remove(b);
}

/* ssi: the subdivision counters in the summary; --quiet, --threads and --tol. The two birds
 * of the hummingbird scenario are bicubic B-splines, which take the subdivision route; the
 * B-spline Cardan parts of cross_through_yoke (planes and quadrics, fast) try the flags. */
static void test_ssi_flags(void)
{
    char a[128], b[128], json[128], args[1200];
    snprintf(a, sizeof a, "/tmp/colibri_cli_ssi_%ld_a.step", (long)getpid());
    snprintf(b, sizeof b, "/tmp/colibri_cli_ssi_%ld_b.step", (long)getpid());
    snprintf(json, sizeof json, "/tmp/colibri_cli_ssi_%ld.json", (long)getpid());
    snprintf(args, sizeof args, "model hummingbird -o %s", a);
    cli_expect(args, 0, "valid");
    snprintf(args, sizeof args,
             "model hummingbird -o %s --rotate 0.2 0.3 1 40 --translate 0.4 0.25 0.15 "
             "--wing-angle 5",
             b);
    cli_expect(args, 0, "valid");
    snprintf(args, sizeof args, "ssi %s %s --threads 2", a, b);
    cli_expect(args, 0, "refused 0\nsubdivision      ");
    double pairs = number_after("subdivision      ");
    const char *sub = strstr(cli_out, "subdivision      ");
    const char *ex = sub ? strstr(sub, " patch pairs, ") : NULL;
    double subpairs = ex ? strtod(ex + strlen(" patch pairs, "), NULL) : NAN;
    CHECK(pairs > 0 && subpairs >= pairs && ex && strstr(ex, " sub-patch pairs examined\n"),
          "birds: %g pairs subdivided, %g sub-pairs:\n%s", pairs, subpairs, cli_out);

    snprintf(args, sizeof args, "model cardan cross_through_yoke --nurbs -o %s --out-b %s", a, b);
    cli_expect(args, 0, "A n B");
    snprintf(args, sizeof args, "ssi %s %s", a, b);
    cli_expect(args, 0, "subdivision      0 patch pairs, 0 sub-patch pairs examined\n");
    /* --quiet: nothing printed, the same verdict, the JSON still written. */
    remove(json);
    snprintf(args, sizeof args, "ssi %s %s --quiet --threads 1 --json %s", a, b, json);
    int code = cli_run(args);
    CHECK(code == 0 && cli_out[0] == '\0', "%s: exit %d, output:\n%s", args, code, cli_out);
    char *text = slurp(json);
    CHECK(text && strstr(text, "\"branches\": [") && strstr(text, "\"not_certified\": []") &&
              strstr(text, "\"certified\": true") &&
              strstr(text, "\"pairs\": {\"certified\": ") &&
              strstr(text, "\"within_tolerance\": [") && strstr(text, "\"coincident\": ["),
          "%s: JSON %s", args, text ? text : "missing");
    free(text);
    remove(json);
    snprintf(args, sizeof args, "ssi --quiet %s %s --threads 0", a, b);
    code = cli_run(args);
    CHECK(code == 0 && cli_out[0] == '\0', "%s: exit %d, output:\n%s", args, code, cli_out);
    /* Errors still speak. */
    snprintf(args, sizeof args, "ssi --quiet %s /nonexistent/b.step", a);
    cli_expect(args, 2, "b.step: cannot open");
    snprintf(args, sizeof args, "ssi %s %s --quiet --json /nonexistent/dir/x.json", a, b);
    cli_expect(args, 2, "cannot write /nonexistent/dir/x.json");
    static const char *const bad[] = {"--threads -1", "--threads abc", "--threads ''",
                                      "--threads 1e3", "--threads 5000"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "ssi %s %s --quiet %s", a, b, bad[k]);
        cli_expect(args, 2, "--threads needs a count in [0, 4096]");
    }
    /* B moved away: no face pair is left; a zero axis is refused. */
    snprintf(args, sizeof args, "ssi %s %s --rotate-b 0 0 1 30 --translate-b 1000 0 0", a, b);
    cli_expect(args, 0, "patch pairs      0:");
    snprintf(args, sizeof args, "ssi %s %s --rotate-b 0 0 0 30", a, b);
    cli_expect(args, 2, "--rotate-b: the axis is zero");
    snprintf(args, sizeof args, "ssi %s %s --translate-b 1 2", a, b);
    cli_expect(args, 2, "--translate-b needs 3 numbers");
    snprintf(args, sizeof args, "ssi %s %s --max-phi-degree 0", a, b);
    cli_expect(args, 2, "--max-phi-degree needs a degree in [1, 64]");
    snprintf(args, sizeof args, "ssi %s %s --max-phi-degree 18 --quiet", a, b);
    cli_expect(args, 0, "");
    snprintf(args, sizeof args, "ssi %s %s --tol inf", a, b);
    cli_expect(args, 2, "--tol needs a positive number");
    snprintf(args, sizeof args, "ssi %s %s --threads", a, b);
    cli_expect(args, 2, "unknown or incomplete option '--threads'");
    remove(a);
    remove(b);
}

/* A face pair of `colibri ssi --json`: its curves and their points. */
typedef struct {
    int fa, fb, curves;
    long points;
} svg_pair;

/* The face pairs of the branches in an ssi JSON text (curves only: the scenario below has no
 * isolated points); returns how many, at most max. */
static int json_pairs(svg_pair *out, int max, const char *json)
{
    int n = 0;
    for (const char *at = strstr(json, "{\"face_a\": "); at && n < max;
         at = strstr(at + 1, "{\"face_a\": ")) {
        int fa, fb;
        char kind[16];
        if (sscanf(at, "{\"face_a\": %d, \"face_b\": %d, \"kind\": \"%15[a-z]\"", &fa, &fb,
                   kind) != 3)
            break;
        const char *uv = strstr(at, "\"uv_a\": ["), *end = uv ? strstr(uv, "]]") : NULL;
        long pts = 0;
        for (const char *c = uv ? uv + strlen("\"uv_a\": [") : end; c && c < end; c++)
            pts += *c == '[';
        int k = 0;
        while (k < n && (out[k].fa != fa || out[k].fb != fb))
            k++;
        if (k == n)
            out[n++] = (svg_pair){fa, fb, 0, 0};
        out[k].curves += !strcmp(kind, "curve");
        out[k].points += pts;
    }
    return n;
}

/* In text[0, len): the curve polylines and their points; the x coordinates of the curve
 * points that are strict local extrema along their polyline (folds in u) with no critical
 * mark within 2 pixels are counted in *unmarked, the extrema in *folds. */
static void svg_curves(const char *text, size_t len, int *polylines, long *points, int *folds,
                       int *unmarked)
{
    static double x[1 << 16], y[1 << 16];
    const char *end = text + len;
    *polylines = *folds = *unmarked = 0;
    *points = 0;
    for (const char *at = strstr(text, "<polyline class=\"curve\""); at && at < end;
         at = strstr(at + 1, "<polyline class=\"curve\"")) {
        (*polylines)++;
        const char *p = strstr(at, "points=\"") + 8;
        int n = 0, used;
        while (n < (1 << 16) && sscanf(p, "%lf,%lf%n", x + n, y + n, &used) == 2) {
            n++;
            p += used;
        }
        *points += n;
        for (int i = 1; i + 1 < n; i++) {
            double a = x[i] - x[i - 1], b = x[i] - x[i + 1];
            if (!((a > 0.05 && b > 0.05) || (a < -0.05 && b < -0.05)))
                continue;
            (*folds)++;
            int marked = 0;
            for (const char *m = strstr(text, "<rect class=\"critical\""); m && m < end && !marked;
                 m = strstr(m + 1, "<rect class=\"critical\"")) {
                double mx, my;
                if (sscanf(m, "<rect class=\"critical\" x=\"%lf\" y=\"%lf\"", &mx, &my) == 2)
                    marked = hypot(mx + 4 - x[i], my + 4 - y[i]) <= 2;
            }
            *unmarked += !marked;
        }
    }
}

/* ssi --svg: one picture per face pair with output in the --json, each a whole SVG document
 * whose two panels draw every point of the pair's curves exactly once (a curve may be broken
 * where an angle wraps round, never less than one polyline per curve); on the parameterised
 * side (B: the analytic cross is implicitised) every fold of a curve in u carries a critical
 * mark, and critical marks appear somewhere. The cross's cylinders against the bird's bicubic
 * faces take the algebraic route, whose topology graphs the marks come from. A --svg path that
 * is a regular file is refused with exit 2. */
static void test_ssi_svg(void)
{
    char a[128], b[128], json[128], dir[128], args[1200];
    snprintf(a, sizeof a, "/tmp/colibri_cli_svg_%ld_a.step", (long)getpid());
    snprintf(b, sizeof b, "/tmp/colibri_cli_svg_%ld_b.step", (long)getpid());
    snprintf(json, sizeof json, "/tmp/colibri_cli_svg_%ld.json", (long)getpid());
    snprintf(dir, sizeof dir, "/tmp/colibri_cli_svg_%ld", (long)getpid());
    snprintf(args, sizeof args, "model cardan cross -o %s", a);
    cli_expect(args, 0, "valid");
    snprintf(args, sizeof args, "model hummingbird -o %s --scale 2 --rotate 0 0 1 20", b);
    cli_expect(args, 0, "valid");
    snprintf(args, sizeof args, "ssi %s %s --quiet --json %s --svg %s", a, b, json, dir);
    int code = cli_run(args);
    CHECK(code == 0, "%s: exit %d:\n%s", args, code, cli_out);
    char *text = slurp(json);
    static svg_pair pairs[1024];
    int np = text ? json_pairs(pairs, 1024, text) : 0;
    free(text);
    CHECK(np > 0, "%s: no face pairs in the JSON", args);
    int files = 0;
    DIR *d = opendir(dir);
    CHECK(d != NULL, "%s: no directory %s", args, dir);
    for (struct dirent *e; d && (e = readdir(d));)
        files += strstr(e->d_name, ".svg") != NULL;
    if (d)
        closedir(d);
    CHECK(files == np, "%s: %d pictures for %d face pairs", args, files, np);
    int with_critical = 0, folds = 0;
    for (int k = 0; k < np; k++) {
        char path[256];
        snprintf(path, sizeof path, "%s/pair_%d_%d.svg", dir, pairs[k].fa, pairs[k].fb);
        size_t size;
        char *svg = slurp_size(path, &size);
        CHECK(svg != NULL, "%s missing", path);
        if (!svg)
            continue;
        CHECK(!strncmp(svg, "<svg", 4) && size > 8 && !strcmp(svg + size - 7, "</svg>\n"),
              "%s: not a whole SVG document", path);
        const char *pb = strstr(svg, "<g class=\"panel\" id=\"B\">");
        CHECK(pb != NULL, "%s: no panel B", path);
        if (!pb) {
            free(svg);
            continue;
        }
        for (int side = 0; side < 2; side++) {
            const char *from = side ? pb : svg;
            size_t len = side ? size - (size_t)(pb - svg) : (size_t)(pb - svg);
            int lines, f, unmarked;
            long points;
            svg_curves(from, len, &lines, &points, &f, &unmarked);
            CHECK(lines >= pairs[k].curves && points == pairs[k].points,
                  "%s panel %c: %d curve polylines of %ld points, the JSON has %d curves of "
                  "%ld points",
                  path, side ? 'B' : 'A', lines, points, pairs[k].curves, pairs[k].points);
            CHECK(!side || unmarked == 0, "%s: %d of %d folds of B's curves lack a critical "
                  "mark", path, unmarked, f);
            folds += side * f;
        }
        with_critical += strstr(svg, "<rect class=\"critical\"") != NULL;
        free(svg);
        remove(path);
    }
    CHECK(with_critical > 0 && folds > 0, "%s: %d pictures with critical marks, %d folds",
          args, with_critical, folds);
    rmdir(dir);
    snprintf(args, sizeof args, "ssi %s %s --quiet --svg %s", a, b, json);
    cli_expect(args, 2, "exists and is not a directory");
    remove(json);
    remove(a);
    remove(b);
}

int main(void)
{
    const char *shared = getenv("COLIBRI_SHARED");
    char args[1024];
    cli_expect("", 2, "COMMAND [options] [files]");
    cli_expect("--help", 0, "commands:");
    cli_expect("--version", 0, "colibri ");
    cli_expect("frobnicate", 2, "unknown command 'frobnicate'");
    cli_expect("info --help", 0, "usage: colibri info");
    cli_expect("info", 2, "usage: colibri info");
    cli_expect("info a b", 2, "usage: colibri info");
    cli_expect("info /nonexistent.bpt", 2, "/nonexistent.bpt: cannot open");
    snprintf(args, sizeof args, "info '%s/models/teapot.bpt'", shared ? shared : "../shared");
    cli_expect(args, 0, "32 patches");
    snprintf(args, sizeof args, "info '%s/models/SOURCES.md'", shared ? shared : "../shared");
    cli_expect(args, 2, "SOURCES.md: unknown model format");
    /* A .bpt path that cannot be opened says so. */
    snprintf(args, sizeof args, "info /dev/null/x.bpt");
    cli_expect(args, 2, "x.bpt: cannot open");
    /* STEP models: text and JSON summaries, rejected files, bad options. */
    const char *sh = shared ? shared : "../shared";
    snprintf(args, sizeof args, "info '%s/models/ujoint_cross.step'", sh);
    cli_expect(args, 0, "1 solid, 1 shell, 8 faces, 14 edges, 8 vertices");
    cli_expect(args, 0, "validation (tolerance 1e-07): valid");
    snprintf(args, sizeof args, "info --json '%s/models/ujoint_fork.step'", sh);
    cli_expect(args, 0, "\"solids\": 1, \"shells\": 1, \"faces\": 17, \"edges\": 54");
    cli_expect(args, 0, "\"surface_types\": {\"cylinder\": 7, \"plane\": 7, \"sphere\": 3}");
    cli_expect(args, 0, "\"valid\": true, \"problems\": []");
    snprintf(args, sizeof args, "info '%s/models/trj5_k1-al-214.stp' --json", sh);
    cli_expect(args, 0, "\"surface_types\": {\"bspline\": 39}");
    CHECK(strstr(cli_out, "\"unit_mm\": 10,") != NULL, "trj5:\n%s", cli_out);
    /* Volume and area in the file's unit, cm: Open CASCADE's 7936.1475 mm^3 and 4952.8495
     * mm^2, to 1e-6. */
    double trj5_v = json_number("volume"), trj5_a = json_number("area");
    CHECK(fabs(trj5_v - 7.9361475) <= 1e-6 * 7.9361475 &&
              fabs(trj5_a - 49.528495) <= 1e-6 * 49.528495,
          "trj5: volume %.10g cm^3, area %.10g cm^2", trj5_v, trj5_a);
    /* linkrods' edges stray up to 4.14e-4 from their surfaces, twenty times the file's 2e-5:
     * the reader raises edge tolerances to their deviation (+5%), and the model is valid. The
     * largest is within 10% of Open CASCADE's 4.13e-4. */
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --json", sh);
    cli_expect(args, 0, "\"valid\": true");
    CHECK(strstr(cli_out, "\"edges_over_cap\": 0") && strstr(cli_out, "\"mass_error\": null}"),
          "linkrods:\n%s", cli_out);
    double volume = json_number("volume");
    CHECK(fabs(volume - 3.847013) <= 1e-6 * 3.847013, "linkrods: volume %.10g (OCCT 3.847013)",
          volume);
    int raised = (int)json_number("edges_tol_raised");
    double largest = json_number("max_edge_tol");
    CHECK(raised > 0 && raised <= 108 && fabs(largest - 4.13e-4) <= 0.1 * 4.13e-4,
          "linkrods: %d edge tolerances raised, largest %g", raised, largest);
    /* Without the volume and area (--no-mass), which take a second here. */
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --no-mass", sh);
    char want[200];
    snprintf(want, sizeof want,
             "edge tolerances: %d raised above the file's 2e-05, largest %.3g (cap 0.000561)",
             raised, largest);
    cli_expect(args, 0, want);
    CHECK(strstr(cli_out, "validation (tolerance 2e-05): valid") && !strstr(cli_out, "volume"),
          "linkrods --no-mass:\n%s", cli_out);
    snprintf(args, sizeof args, "info '%s/models/linkrods.step' --no-mass --tol 5e-4 --json", sh);
    cli_expect(args, 0, "\"tolerance\": 0.00050000000000000001, \"valid\": true");
    CHECK(strstr(cli_out, "\"volume\": null, \"area\": null, \"mass_error\": \"not computed "
                          "(--no-mass)\"}\n"),
          "linkrods --no-mass --json:\n%s", cli_out);
    snprintf(args, sizeof args, "info '%s/models/ujoint_cross.step' --json", sh);
    cli_expect(args, 0, "\"edges_tol_raised\": 0, \"edges_over_cap\": 0");
    char bad[64];
    snprintf(bad, sizeof bad, "/tmp/colibri_cli_bad_%ld.step", (long)getpid());
    FILE *f = fopen(bad, "w");
    fputs("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=MANIFOLD_SOLID_BREP('',#2);\n"
          "#2=CLOSED_SHELL('',(#3));\nENDSEC;\nEND-ISO-10303-21;\n",
          f);
    fclose(f);
    snprintf(args, sizeof args, "info %s", bad);
    snprintf(want, sizeof want, "%s:6: #2 CLOSED_SHELL: face: #3 is not defined", bad);
    cli_expect(args, 2, want);
    remove(bad);
    cli_expect("info /nonexistent/x.step --json", 2, "x.step: cannot open");
    cli_expect("info x.step --tol abc", 2, "--tol needs a positive number");
    cli_expect("info x.step --bogus", 2, "usage: colibri info");
    test_bad_step(sh);
    test_other_commands(sh);
    test_info_mass(sh);
    test_model_cardan();
    test_ssi_flags();
    test_ssi_svg();
    return check_report("cli");
}
