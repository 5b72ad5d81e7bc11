/* Downstream consumer: links the installed libkin, checks header and library
 * versions agree, that the three-bar analysis works and that a JSON model
 * loads. */
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
    if (an.rank != 2 || an.m != 2 || an.s != 1) return 1;
    /* a model file in memory: pulls jansson into the static link */
    static const char model[] =
        "{\"dimension\": 2, \"joints\": [{\"xyz\": [0, 0], \"free\": [false, false]},"
        " {\"xyz\": [1, 0]}, {\"xyz\": [1, 1]}, {\"xyz\": [0, 1], \"free\": [false, false]}],"
        " \"bars\": [{\"joints\": [0, 1]}, {\"joints\": [1, 2]}, {\"joints\": [2, 3]}]}";
    char err[256];
    if (kin_assembly_load_string(model, sizeof model - 1, &a, err, sizeof err) || kin_analyse(a, &an)) {
        fprintf(stderr, "consumer: %s\n", err);
        return 1;
    }
    printf("consumer: four-bar from JSON, m_internal=%d\n", an.m_internal);
    kin_assembly_free(a);
    return an.m_internal == 1 ? 0 : 1;
}
