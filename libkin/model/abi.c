/* Size-prefixed public structs (docs/abi.md): every options and info struct
 * starts with `size_t size`, the sizeof of the struct the caller compiled
 * against. That size must be one of the struct's published layouts (the
 * table generated from the headers, model/abi_layouts.h); the library reads
 * and writes only that layout's fields, so a host built against older
 * headers keeps working when a struct grows at its end, and one built
 * against newer headers (or with a size nobody set) is refused with
 * KIN_EINVAL rather than misread. */
#include <string.h>

#include "model/internal.h"

const kin__abi_type kin__abi_types[KIN__ABI_NTYPES] = {KIN__ABI_TABLE};

size_t kin__abi_size(const void *p)
{
    size_t s;
    memcpy(&s, p, sizeof s);
    return s;
}

size_t kin__abi_end(const kin__abi_type *t, size_t size)
{
    for (int i = 0; i < t->nlayouts; ++i)
        if (t->size[i] == size) return t->end[i];
    return 0;
}

int kin__abi_check(const void *p, const kin__abi_type *t)
{
    return kin__abi_end(t, kin__abi_size(p)) ? KIN_OK : KIN_EINVAL;
}

static size_t current_size(const kin__abi_type *t) { return t->size[t->nlayouts - 1]; }

void kin__abi_read(void *local, const void *user, const kin__abi_type *t)
{
    size_t cur = current_size(t);
    memcpy(local, user, kin__abi_end(t, kin__abi_size(user)));
    memcpy(local, &cur, sizeof cur);
}

void kin__abi_write(void *user, const void *local, const kin__abi_type *t)
{
    size_t end = kin__abi_end(t, kin__abi_size(user));
    if (end > sizeof(size_t))
        memcpy((char *)user + sizeof(size_t), (const char *)local + sizeof(size_t), end - sizeof(size_t));
}

void kin__abi_zero(void *user)
{
    size_t s = kin__abi_size(user);
    if (s > sizeof s) memset((char *)user + sizeof s, 0, s - sizeof s);
}

int kin__abi_init(void *p, size_t size, const void *defaults, const kin__abi_type *t)
{
    if (!p) return KIN_ENULL;
    size_t end = kin__abi_end(t, size);
    if (!end) return KIN_EINVAL;
    memset(p, 0, size); /* padding too: the struct is compared and copied bytewise */
    memcpy(p, defaults, end);
    memcpy(p, &size, sizeof size);
    return KIN_OK;
}

int kin__abi_entry(kin_assembly *a, void *info, const kin__abi_type *it, const void *opt, void *local,
                   const kin__abi_type *ot)
{
    if (info) {
        if (kin__abi_check(info, it))
            return a ? kin__fail(a, KIN_EINVAL, "info->size = %zu: set it to sizeof(%s)", kin__abi_size(info),
                                 it->name)
                     : KIN_EINVAL;
        kin__abi_zero(info);
    }
    if (!a) return KIN_ENULL;
    if (opt) {
        if (kin__abi_check(opt, ot))
            return kin__fail(a, KIN_EINVAL, "options->size = %zu: not set by %s_default() of this libkin",
                             kin__abi_size(opt), ot->name);
        kin__abi_read(local, opt, ot);
    }
    return KIN_OK;
}
