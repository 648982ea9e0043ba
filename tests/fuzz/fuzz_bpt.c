/* libFuzzer target: the .bpt reader on arbitrary bytes must return a status, never crash,
 * leak or read out of bounds, and on success hand back valid surfaces. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "io/bpt.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cb_nurbs_surface_struct *patches;
    int n;
    cb_error err;
    if (cb_bpt_read_buffer(&patches, &n, (const char *)data, size, "fuzz.bpt", &err) == CB_OK) {
        for (int k = 0; k < n; k++)
            if (cb_nurbs_surface_validate(&patches[k], &err) != CB_OK)
                abort();
        cb_nurbs_surface_array_free(patches, n);
    }
    return 0;
}
