/* Size-prefixed public structs (docs/abi.md): every options and info struct
 * starts with `size_t size`, the size the caller compiled against. The
 * library reads and writes only that many bytes, so a host built against
 * older headers keeps working when a struct grows at its end, and one built
 * against newer headers is refused with KIN_EINVAL rather than misread. */
#include <string.h>

#include "model/internal.h"

size_t kin__abi_size(const void *p)
{
    size_t s;
    memcpy(&s, p, sizeof s);
    return s;
}

int kin__abi_check(const void *p, size_t min_size, size_t cur_size)
{
    size_t s = kin__abi_size(p);
    return s >= min_size && s <= cur_size ? KIN_OK : KIN_EINVAL;
}

void kin__abi_read(void *local, const void *user, size_t cur_size)
{
    size_t s = kin__abi_size(user);
    memcpy(local, user, s < cur_size ? s : cur_size);
    memcpy(local, &cur_size, sizeof cur_size);
}

void kin__abi_write(void *user, const void *local, size_t cur_size)
{
    size_t s = kin__abi_size(user);
    memcpy((char *)user + sizeof s, (const char *)local + sizeof s, (s < cur_size ? s : cur_size) - sizeof s);
}

void kin__abi_zero(void *user)
{
    size_t s = kin__abi_size(user);
    if (s > sizeof s) memset((char *)user + sizeof s, 0, s - sizeof s);
}

int kin__abi_entry(kin_assembly *a, void *info, size_t info_min, size_t info_cur, const char *info_type,
                   const void *opt, size_t opt_min, void *local, size_t opt_cur, const char *opt_default)
{
    if (info) {
        if (kin__abi_check(info, info_min, info_cur))
            return a ? kin__fail(a, KIN_EINVAL, "info->size = %zu: set it to sizeof(%s)", kin__abi_size(info),
                                 info_type)
                     : KIN_EINVAL;
        kin__abi_zero(info);
    }
    if (!a) return KIN_ENULL;
    if (opt) {
        if (kin__abi_check(opt, opt_min, opt_cur))
            return kin__fail(a, KIN_EINVAL, "options->size = %zu: not set by %s() of this libkin",
                             kin__abi_size(opt), opt_default);
        kin__abi_read(local, opt, opt_cur);
    }
    return KIN_OK;
}
