/* status.h — status codes and error messages shared by every Colibri module.
 *
 * Every fallible function returns a cb_status and, when given a non-NULL cb_error, fills it with
 * a message that says what failed and where (control point index, knot index, file and line).
 * Nothing in the library exits or aborts on bad input. */
#ifndef CB_STATUS_H
#define CB_STATUS_H

#include <stddef.h>

typedef enum {
    CB_OK = 0,
    CB_ERR_INVALID = -1,     /* input violates a documented precondition */
    CB_ERR_NOMEM = -2,       /* allocation failed */
    CB_ERR_IO = -3,          /* a file could not be opened, read or written */
    CB_ERR_PARSE = -4,       /* a file is not of the expected format */
    CB_ERR_UNSUPPORTED = -5, /* valid input the code does not handle yet */
    CB_ERR_NUMERIC = -6,     /* a numerical method did not reach its tolerance */
    CB_ERR_CANCELLED = -7    /* the caller asked to stop */
} cb_status;

#define CB_ERROR_MSG_LEN 512

typedef struct {
    cb_status status;
    char msg[CB_ERROR_MSG_LEN];
} cb_error;

/* Short fixed name of a status ("ok", "invalid input", ...). */
const char *cb_status_name(cb_status st);

void cb_error_clear(cb_error *err);

/* Records st and a printf-style message in err (if err is non-NULL) and returns st, so that a
 * failure reads `return cb_error_set(err, CB_ERR_INVALID, "knot %d ...", i);`. */
cb_status cb_error_set(cb_error *err, cb_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prepends context ("face 12: ") to the message already in err; returns err's status. */
cb_status cb_error_prefix(cb_error *err, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#endif
