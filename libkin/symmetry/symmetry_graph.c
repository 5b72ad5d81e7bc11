/* The automorphism group of an assembly's bar graph with coloured joints
 * and bars, from nauty's Traces.
 *
 * nauty colours vertices only, so each bar becomes a vertex of its own
 * between its two joints, coloured by the bar's colour (in cells after
 * every joint cell: a bar vertex never goes to a joint). Traces returns
 * generators of the group (through TracesOptions.generators: no callback,
 * no state of ours outside this call); the group they generate is
 * enumerated by closure (breadth first, a hash set of the joint
 * permutations), the order Traces reports checked first against the cap.
 * Traces keeps its work arrays in thread-local storage (nauty is built with
 * USE_TLS): released with the *_freedyn calls after every use. */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <nauty/traces.h>

#include "model/internal.h"
#include "symmetry/symmetry_graph.h"

typedef struct vkey {
    int kind;   /* 0 joint, 1 bar */
    int colour;
    int vertex;
} vkey;

static int cmp_vkey(const void *pa, const void *pb)
{
    const vkey *a = pa, *b = pb;
    if (a->kind != b->kind) return a->kind < b->kind ? -1 : 1;
    if (a->colour != b->colour) return a->colour < b->colour ? -1 : 1;
    return (a->vertex > b->vertex) - (a->vertex < b->vertex);
}

static uint64_t hash_perm(const int *p, int n)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a over the ints */
    for (int i = 0; i < n; ++i) {
        h ^= (uint64_t)(unsigned)p[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* insert perm number k (stored at perms + k*n) into the open-addressing
 * table (size mask+1, entries k+1, 0 empty); returns 0 if an equal one is
 * there already */
static int insert_perm(int *table, size_t mask, const int *perms, int n, int k)
{
    const int *p = perms + (size_t)k * n;
    size_t h = (size_t)hash_perm(p, n) & mask;
    while (table[h]) {
        if (!memcmp(perms + (size_t)(table[h] - 1) * n, p, sizeof(int) * (size_t)n)) return 0;
        h = (h + 1) & mask;
    }
    table[h] = k + 1;
    return 1;
}

static void free_traces_state(permnode **gens)
{
    if (*gens) freeschreier(NULL, gens);
    traces_freedyn();
    schreier_freedyn();
    nausparse_freedyn();
    nautil_freedyn();
}

int kin__graph_automorphisms(int nj, int nb, const int *bars, const int *jcolour, const int *bcolour,
                             int max_count, int **perms, int *count)
{
    *perms = NULL;
    *count = 0;
    int nv = nj + nb, rc = KIN_OK;
    size_t nde = 4 * (size_t)nb;
    vkey *keys = malloc(sizeof(vkey) * (size_t)nv);
    int *lab = malloc(sizeof(int) * (size_t)nv), *ptn = malloc(sizeof(int) * (size_t)nv);
    int *orbits = malloc(sizeof(int) * (size_t)nv), *deg = calloc((size_t)nv, sizeof(int));
    int *edges = malloc(sizeof(int) * nde);
    size_t *start = malloc(sizeof(size_t) * (size_t)nv);
    int *P = NULL, *table = NULL;
    permnode *gens = NULL;
    if (!keys || !lab || !ptn || !orbits || !deg || !edges || !start) {
        rc = KIN_ENOMEM;
        goto done;
    }
    /* adjacency: joint j - bar vertex nj+k for both ends of bar k */
    for (int k = 0; k < nb; ++k) {
        deg[bars[2 * k]]++, deg[bars[2 * k + 1]]++;
        deg[nj + k] = 2;
    }
    size_t off = 0;
    for (int v = 0; v < nv; ++v) start[v] = off, off += (size_t)deg[v], deg[v] = 0;
    for (int k = 0; k < nb; ++k)
        for (int e = 0; e < 2; ++e) {
            int j = bars[2 * k + e];
            edges[start[j] + (size_t)deg[j]++] = nj + k;
            edges[start[nj + k] + (size_t)deg[nj + k]++] = j;
        }
    /* the colouring as nauty's partition: cells of equal (kind, colour) */
    for (int v = 0; v < nv; ++v) {
        keys[v].kind = v >= nj;
        keys[v].colour = v < nj ? jcolour[v] : bcolour[v - nj];
        keys[v].vertex = v;
    }
    qsort(keys, (size_t)nv, sizeof(vkey), cmp_vkey);
    for (int i = 0; i < nv; ++i) {
        lab[i] = keys[i].vertex;
        ptn[i] = i + 1 < nv && keys[i + 1].kind == keys[i].kind && keys[i + 1].colour == keys[i].colour;
    }

    sparsegraph sg;
    memset(&sg, 0, sizeof sg);
    sg.nv = nv, sg.nde = nde, sg.v = start, sg.d = deg, sg.e = edges;
    sg.vlen = (size_t)nv, sg.dlen = (size_t)nv, sg.elen = nde;
    DEFAULTOPTIONS_TRACES(opt);
    opt.defaultptn = FALSE;
    opt.generators = &gens;
    TracesStats stats;
    memset(&stats, 0, sizeof stats);
    Traces(&sg, lab, ptn, orbits, &opt, &stats, NULL);
    if (stats.errstatus) {
        rc = KIN_ENOMEM; /* Traces reports only allocation trouble here */
        goto done;
    }
    /* the order grpsize1 * 10^grpsize2, against the cap before enumerating */
    double order = stats.grpsize1;
    for (int i = 0; i < stats.grpsize2 && order <= (double)INT_MAX; ++i) order *= 10.0;
    if (order > (double)max_count + 0.5) {
        *count = order >= (double)INT_MAX ? INT_MAX : (int)(order + 0.5);
        rc = KIN_ELIMIT;
        goto done;
    }
    int want = (int)(order + 0.5), ngen = 0;
    if (want < 1) want = 1;
    size_t tsize = 1;
    while (tsize < 2 * (size_t)want) tsize <<= 1;
    P = malloc(sizeof(int) * (size_t)want * (size_t)nj);
    table = calloc(tsize, sizeof(int));
    if (!P || !table) {
        rc = KIN_ENOMEM;
        goto done;
    }
    /* the generators, in place of the first elements after the identity:
     * they are read from nauty's list once and the closure uses them from P */
    for (int i = 0; i < nj; ++i) P[i] = i;
    int n = 1;
    insert_perm(table, tsize - 1, P, nj, 0);
    int *gen_index = NULL;
    if (gens) {
        permnode *g = gens;
        do {
            ++ngen;
            g = g->next;
        } while (g != gens);
    }
    gen_index = malloc(sizeof(int) * (size_t)(ngen > 0 ? ngen : 1));
    if (!gen_index) {
        rc = KIN_ENOMEM;
        goto done;
    }
    /* generators that are new group elements are stored; gen_index keeps
     * where each one lives (a generator equal to the identity, which Traces
     * does not return, or to another is skipped) */
    int ng = 0;
    if (gens) {
        permnode *g = gens;
        do {
            if (n < want) {
                memcpy(P + (size_t)n * nj, g->p, sizeof(int) * (size_t)nj);
                if (insert_perm(table, tsize - 1, P, nj, n)) gen_index[ng++] = n++;
            }
            g = g->next;
        } while (g != gens);
    }
    /* closure: every element times every generator, until nothing is new */
    int *tmp = malloc(sizeof(int) * (size_t)nj);
    if (!tmp) {
        free(gen_index);
        rc = KIN_ENOMEM;
        goto done;
    }
    for (int e = 0; e < n; ++e)
        for (int q = 0; q < ng; ++q) {
            const int *pe = P + (size_t)e * nj, *pg = P + (size_t)gen_index[q] * nj;
            for (int i = 0; i < nj; ++i) tmp[i] = pg[pe[i]];
            if (n == want) {
                /* every slot used: a new element would exceed the order */
                int found = 0;
                size_t h = (size_t)hash_perm(tmp, nj) & (tsize - 1);
                while (table[h] && !found) {
                    found = !memcmp(P + (size_t)(table[h] - 1) * nj, tmp, sizeof(int) * (size_t)nj);
                    h = (h + 1) & (tsize - 1);
                }
                if (!found) rc = KIN_ELIMIT; /* Traces' order was wrong: never seen */
                continue;
            }
            memcpy(P + (size_t)n * nj, tmp, sizeof(int) * (size_t)nj);
            if (insert_perm(table, tsize - 1, P, nj, n)) ++n;
        }
    free(tmp);
    free(gen_index);
    if (rc) goto done;
    *perms = P;
    *count = n;
    P = NULL;
done:
    free_traces_state(&gens);
    free(keys), free(lab), free(ptn), free(orbits), free(deg), free(edges), free(start);
    free(P), free(table);
    return rc;
}
