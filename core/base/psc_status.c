/* SPDX-License-Identifier: MIT */
/* psc_status.c - human-readable status codes. */
#include "base/psc_types.h"

const char *psc_status_str(psc_status_t s)
{
    switch (s) {
    case PSC_OK: return "ok";
    case PSC_ERR_ARG: return "invalid argument";
    case PSC_ERR_TRUNCATED: return "truncated data";
    case PSC_ERR_MAGIC: return "not a Periscope scene pack (bad magic)";
    case PSC_ERR_VERSION: return "unsupported format version";
    case PSC_ERR_CRC: return "checksum mismatch (corrupt data)";
    case PSC_ERR_CORRUPT: return "inconsistent or out-of-range field";
    case PSC_ERR_TOO_LARGE: return "dimension exceeds the compiled-in limits";
    case PSC_ERR_NOMEM: return "buffer too small";
    case PSC_ERR_UNSUPPORTED: return "not supported by this build";
    }
    return "unknown status";
}
