/* Progress callbacks of the handle's long loops (kin_progress.h). */
#include "model/internal.h"

int kin_set_progress(kin_assembly *a, kin_progress_fn fn, void *user)
{
    if (!a) return KIN_ENULL;
    a->progress = fn;
    a->progress_user = fn ? user : NULL;
    return KIN_OK;
}

int kin__progress(const kin_assembly *a, double done, double total)
{
    if (!a->progress) return 0;
    if (!(done >= 0.0)) done = 0.0;
    if (done > total) done = total;
    return a->progress(a->progress_user, done, total) != 0;
}
