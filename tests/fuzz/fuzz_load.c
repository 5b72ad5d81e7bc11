/* libFuzzer harness: the C model loader (kin_assembly_load_string) on any
 * bytes. Every input must give KIN_OK with a handle or a status code without
 * one, and no sanitizer report. */
#include <stddef.h>
#include <stdint.h>

#include "libkin.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    kin_assembly *a = NULL;
    char err[256];
    int rc = kin_assembly_load_string((const char *)data, size, &a, err, sizeof err);
    if ((rc == KIN_OK) != (a != NULL)) __builtin_trap();
    if (a) {
        char *text = NULL;
        size_t len = 0;
        /* what was loaded saves and loads again */
        if (kin_assembly_save_string(a, NULL, &text, &len, err, sizeof err) == KIN_OK) {
            kin_assembly *b = NULL;
            if (kin_assembly_load_string(text, len, &b, err, sizeof err) != KIN_OK) __builtin_trap();
            kin_assembly_free(b);
        }
        kin_free_string(text);
        kin_assembly_free(a);
    }
    return 0;
}
