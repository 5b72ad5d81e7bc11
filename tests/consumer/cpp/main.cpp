// Downstream C++ consumer: every public header, each on its own and then
// through <libkin.h>, compiled as C++ and linked against the installed
// libkin. It fails to link if a header declares its functions without
// C linkage (extern "C"). Creates a four-bar from arrays, analyses it, steps
// along its path, loads a JSON model, and checks the status strings.
#include <libkin/kin_export.h>
#include <libkin/kin_version.h>
#include <libkin/kin_status.h>
#include <libkin/kin_assembly.h>
#include <libkin/kin_progress.h>
#include <libkin/kin_path.h>
#include <libkin/kin_models.h>
#include <libkin/kin_branch.h>
#include <libkin/kin_locate.h>
#include <libkin/kin_follow.h>
#include <libkin/kin_io.h>
#include <libkin/kin_symmetry.h>
#include <libkin.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

int failures = 0;

void check(bool ok, const char *what)
{
    if (!ok) {
        std::fprintf(stderr, "consumer_cpp: FAILED: %s\n", what);
        ++failures;
    }
}

// a C++ object handed through the C callback's user pointer
struct counter {
    int calls;
};

}  // namespace

extern "C" int on_progress(void *user, double, double)
{
    static_cast<counter *>(user)->calls++;
    return 0;
}

int main()
{
    check(kin_version_number() == KIN_VERSION_NUMBER, "header and library versions agree");
    check(std::string(kin_version_string()) == KIN_VERSION_STRING, "version string");

    // status codes and their strings, from the X-macro list
    check(std::string(kin_status_name(KIN_EINVAL)) == "KIN_EINVAL", "kin_status_name");
    check(std::strlen(kin_strerror(KIN_ENOMEM)) > 0, "kin_strerror");
    check(kin_strerror(KIN_OK) != kin_strerror(KIN_EINVAL), "distinct messages");

    // a four-bar linkage from arrays: one internal mechanism
    std::vector<double> xyz = {0, 0, 1, 0, 1, 1, 0, 1};
    std::vector<unsigned char> fixed = {1, 1, 0, 0, 0, 0, 1, 1};
    std::vector<int> bars = {0, 1, 1, 2, 2, 3};
    kin_assembly *a = nullptr;
    char err[256] = "";
    int rc = kin_assembly_create(2, 4, xyz.data(), fixed.data(), 3, bars.data(), nullptr, &a, err, sizeof err);
    check(rc == KIN_OK && a != nullptr, "kin_assembly_create");
    if (!a) return 1;
    check(kin_nfree(a) == 4 && kin_nbars(a) == 3, "counts");

    kin_analysis an = {};
    an.size = sizeof an;
    check(kin_analyse(a, &an) == KIN_OK, "kin_analyse");
    check(an.m_internal == 1 && an.s == 0, "four-bar: one mechanism, no self-stress");

    counter c = {0};
    check(kin_set_progress(a, on_progress, &c) == KIN_OK, "kin_set_progress");

    // a few steps along the path: the bars keep their lengths
    double length = 0.0;
    for (int i = 0; i < 5; ++i) {
        kin_step_info info = {};
        info.size = sizeof info;
        rc = kin_step(a, 0.05, &info);
        check(rc == KIN_OK, "kin_step");
        if (rc != KIN_OK) {
            std::fprintf(stderr, "consumer_cpp: %s: %s\n", kin_status_name(rc), kin_last_error(a));
            break;
        }
        length = kin_path_length(a);
    }
    check(length > 0.2 && length < 0.3, "path length after five steps of 0.05");
    check(kin_max_strain(a) < 1e-10, "bars keep their lengths");

    // errors come back as codes with a message on the handle
    check(kin_step(a, NAN, nullptr) == KIN_EINVAL, "non-finite step refused");
    check(std::strlen(kin_last_error(a)) > 0, "kin_last_error");
    kin_assembly_free(a);

    // the three-bar linkage at R^C (paper Section 5): r = 2, m = 2, s = 1
    a = nullptr;
    check(kin_model_threebar(KIN_THREEBAR_RC, &a) == KIN_OK, "kin_model_threebar");
    if (a) {
        an = kin_analysis();
        an.size = sizeof an;
        check(kin_analyse(a, &an) == KIN_OK && an.rank == 2 && an.m == 2 && an.s == 1, "three-bar at R^C");
        kin_assembly_free(a);
    }

    // a JSON model in memory (jansson inside the library)
    const std::string model =
        "{\"dimension\": 2, \"joints\": [{\"xyz\": [0, 0], \"free\": [false, false]},"
        " {\"xyz\": [1, 0]}, {\"xyz\": [1, 1]}, {\"xyz\": [0, 1], \"free\": [false, false]}],"
        " \"bars\": [{\"joints\": [0, 1]}, {\"joints\": [1, 2]}, {\"joints\": [2, 3]}]}";
    a = nullptr;
    rc = kin_assembly_load_string(model.c_str(), model.size(), &a, err, sizeof err);
    check(rc == KIN_OK, "kin_assembly_load_string");
    if (a) {
        char *text = nullptr;
        size_t len = 0;
        rc = kin_assembly_save_string(a, "four-bar", &text, &len, err, sizeof err);
        check(rc == KIN_OK && text && len == std::strlen(text), "kin_assembly_save_string");
        kin_free_string(text);
        kin_assembly_free(a);
    }
    rc = kin_assembly_load_string("{", 1, &a, err, sizeof err);
    check(rc == KIN_EFORMAT && a == nullptr, "malformed model refused");

    if (failures) return 1;
    std::printf("consumer_cpp: libkin %s from C++: create, analyse, step, load, status strings passed\n",
                kin_version_string());
    return 0;
}
