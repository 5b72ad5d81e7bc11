/* Status messages and version: both generated from the single lists in the
 * public headers. */
#include <stdio.h>
#include <string.h>

#include "model/internal.h"

const char *kin_strerror(int status)
{
    switch (status) {
#define KIN_MSG_(name, value, msg) case value: return msg;
        KIN_STATUS_LIST(KIN_MSG_)
#undef KIN_MSG_
    default: return "unknown status";
    }
}

const char *kin_status_name(int status)
{
    switch (status) {
#define KIN_NAME_(name, value, msg) case value: return #name;
        KIN_STATUS_LIST(KIN_NAME_)
#undef KIN_NAME_
    default: return "KIN_UNKNOWN";
    }
}

int kin_version_number(void) { return KIN_VERSION_NUMBER; }
const char *kin_version_string(void) { return KIN_VERSION_STRING; }

int kin__failv(char *buf, size_t len, int code, const char *fmt, va_list ap)
{
    if (buf && len > 0) {
        int n = snprintf(buf, len, "%s: ", kin_strerror(code));
        if (n < 0) n = 0;
        if ((size_t)n < len) vsnprintf(buf + n, len - (size_t)n, fmt, ap);
    }
    return code;
}

int kin__failbuf(char *buf, size_t len, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    kin__failv(buf, len, code, fmt, ap);
    va_end(ap);
    return code;
}

int kin__fail(kin_assembly *a, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    if (a) kin__failv(a->err, sizeof a->err, code, fmt, ap);
    va_end(ap);
    return code;
}

const char *kin_last_error(const kin_assembly *a)
{
    return a ? a->err : "NULL assembly handle";
}
