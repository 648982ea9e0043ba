/* libFuzzer target: the STEP reader on arbitrary bytes must return a status, never crash,
 * hang, leak or read out of bounds; a body it accepts must survive indexing and validation. */
#include <stddef.h>
#include <stdint.h>

#include "io/step.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cb_topo_body *b = NULL;
    cb_error err;
    if (cb_step_read_buffer(&b, (const char *)data, size, "fuzz.step", &err) == CB_OK) {
        cb_topo_report r;
        cb_topo_report_init(&r);
        cb_topo_validate(&r, b, 0, 3, &err);
        cb_topo_report_clear(&r);
        cb_topo_body_free(b);
    }
    return 0;
}
