/* JSON report pieces (io/json.c): string escaping. */
#include <string.h>

#include "check.h"
#include "io/json.h"

static void expect_escaped(const char *in, const char *want)
{
    char buf[256] = {0};
    FILE *f = tmpfile();
    cb_json_string(f, in);
    rewind(f);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    CHECK(!strcmp(buf, want), "'%s' escaped as %s, expected %s", in, buf, want);
}

int main(void)
{
    expect_escaped("plain", "\"plain\"");
    expect_escaped("", "\"\"");
    expect_escaped("a \"q\" b", "\"a \\\"q\\\" b\"");
    expect_escaped("C:\\dir", "\"C:\\\\dir\"");
    expect_escaped("tab\tnl\n", "\"tab\\u0009nl\\u000a\"");
    expect_escaped("caf\xc3\xa9", "\"caf\xc3\xa9\"");
    return check_report("io_json");
}
