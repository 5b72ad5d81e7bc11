/* Downstream consumer: links the installed libkin, checks header and library
 * versions agree and that the three-bar analysis works. */
#include <stdio.h>

#include <libkin.h>

int main(void)
{
    kin_assembly *a = NULL;
    kin_analysis an = {.size = sizeof an};
    if (kin_version_number() != KIN_VERSION_NUMBER) {
        fprintf(stderr, "version mismatch: header %d, library %d\n", KIN_VERSION_NUMBER,
                kin_version_number());
        return 1;
    }
    if (kin_model_threebar(KIN_THREEBAR_RC, &a) || kin_analyse(a, &an)) return 1;
    printf("consumer: libkin %s, r=%d m=%d s=%d\n", kin_version_string(), an.rank, an.m, an.s);
    kin_assembly_free(a);
    return (an.rank == 2 && an.m == 2 && an.s == 1) ? 0 : 1;
}
