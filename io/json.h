/* json.h — the small pieces of JSON output the reports share. */
#ifndef CB_IO_JSON_H
#define CB_IO_JSON_H

#include <stdio.h>

/* Writes s as a JSON string literal: quotes and backslashes escaped, control characters as
 * \u00XX; other bytes pass through (UTF-8 stays UTF-8). */
void cb_json_string(FILE *out, const char *s);

#endif
