/* btf_ubo_internal.h — what the Bonn-format reader and writer share (internal to materials/btf). */
#ifndef PRW_BTF_UBO_INTERNAL_H
#define PRW_BTF_UBO_INTERNAL_H

#include "btf_cursor.h"
#include "prw_btf_ubo.h"

#endif
