/* Status list, messages and version. */
#include <string.h>

#include "check.h"
#include "libkin.h"

int main(void)
{
    /* every code has its own message and name; unknown codes are handled */
    for (int c = 0; c < KIN_STATUS_COUNT_; ++c) {
        CHECK(strlen(kin_strerror(c)) > 0);
        CHECK(strncmp(kin_status_name(c), "KIN_", 4) == 0);
        for (int d = 0; d < c; ++d) CHECK(strcmp(kin_strerror(c), kin_strerror(d)) != 0);
    }
    CHECK(strcmp(kin_strerror(-1), "unknown status") == 0);
    CHECK(strcmp(kin_strerror(KIN_STATUS_COUNT_), "unknown status") == 0);
    CHECK(strcmp(kin_status_name(KIN_ENOTCONVERGED), "KIN_ENOTCONVERGED") == 0);
    CHECK(kin_version_number() == KIN_VERSION_NUMBER);
    CHECK(strcmp(kin_version_string(), KIN_VERSION_STRING) == 0);
    CHECK(strcmp(kin_last_error(NULL), "NULL assembly handle") == 0);
    TEST_REPORT("test_status");
}
