/* BLAS threads chosen for the matrix size (docs/performance.md). On the
 * small matrices of most structures (H of a few hundred rows) OpenBLAS's
 * threads cost more than they give: the hexagonal sail's follower took 2.8
 * times as long with the default threads on 2 cores as with one. The count
 * is process-wide state of OpenBLAS, so it is changed only for the duration
 * of a call and put back as the caller had it: a count of the calls inside
 * (several threads may follow at once) and the caller's setting, under one
 * mutex; the first call in sets one thread, the last one out restores.
 * OpenBLAS is found at run time (openblas_get_num_threads and
 * openblas_set_num_threads in the library that holds dgemm_, or its
 * dependencies), so the reference BLAS and others link and run unchanged:
 * nothing happens with them. This is the library's only process-wide
 * state, and it is there only because OpenBLAS's is. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"

typedef int (*get_fn)(void);
typedef void (*set_fn)(int);

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static int looked_up;    /* the functions were searched for */
static get_fn get_threads;
static set_fn set_threads;
static int depth;        /* calls inside that asked for one thread */
static int saved;        /* the caller's count, to restore (0: unchanged) */

static void look_up(void)
{
    looked_up = 1;
    Dl_info di;
    /* function and object pointers converted through memcpy (ISO C has no cast) */
    void (*fn)(void) = (void (*)(void))dgemm_, *addr = NULL, *g, *s;
    memcpy(&addr, &fn, sizeof addr);
    if (!dladdr(addr, &di) || !di.dli_fname) return;
    void *h = dlopen(di.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
    if (!h) return;
    g = dlsym(h, "openblas_get_num_threads");
    s = dlsym(h, "openblas_set_num_threads");
    memcpy(&get_threads, &g, sizeof g);
    memcpy(&set_threads, &s, sizeof s);
    if (!get_threads || !set_threads) get_threads = NULL, set_threads = NULL;
    dlclose(h); /* RTLD_NOLOAD: only drops the reference just taken */
}

int kin__blas_threads_small(const kin_assembly *a)
{
    if (!a || a->nf > KIN__BLAS_SMALL) return 0;
    pthread_mutex_lock(&lock);
    if (!looked_up) look_up();
    if (get_threads && depth++ == 0) {
        int n = get_threads();
        saved = 0;
        if (n > 1) {
            saved = n;
            set_threads(1);
        }
    }
    int token = get_threads != NULL;
    pthread_mutex_unlock(&lock);
    return token;
}

void kin__blas_threads_restore(int token)
{
    if (!token) return;
    pthread_mutex_lock(&lock);
    if (--depth == 0 && saved > 0) {
        set_threads(saved);
        saved = 0;
    }
    pthread_mutex_unlock(&lock);
}
