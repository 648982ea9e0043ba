#include "brep/status.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *cb_status_name(cb_status st)
{
    switch (st) {
    case CB_OK: return "ok";
    case CB_ERR_INVALID: return "invalid input";
    case CB_ERR_NOMEM: return "out of memory";
    case CB_ERR_IO: return "i/o error";
    case CB_ERR_PARSE: return "parse error";
    case CB_ERR_UNSUPPORTED: return "unsupported";
    case CB_ERR_NUMERIC: return "numerical failure";
    case CB_ERR_CANCELLED: return "cancelled";
    }
    return "unknown status";
}

void cb_error_clear(cb_error *err)
{
    if (err) {
        err->status = CB_OK;
        err->msg[0] = '\0';
    }
}

cb_status cb_error_set(cb_error *err, cb_status st, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        err->status = st;
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
    }
    return st;
}

cb_status cb_error_prefix(cb_error *err, const char *fmt, ...)
{
    if (!err)
        return CB_OK;
    char old[CB_ERROR_MSG_LEN];
    memcpy(old, err->msg, sizeof old);
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    /* Append as much of the old message as still fits, always NUL-terminated. */
    for (size_t k = 0; len >= 0 && (size_t)len + k + 1 < sizeof err->msg && old[k]; k++) {
        err->msg[len + k] = old[k];
        err->msg[len + k + 1] = '\0';
    }
    return err->status;
}
