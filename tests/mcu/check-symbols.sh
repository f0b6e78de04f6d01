#!/bin/sh
# SPDX-License-Identifier: MIT
# check-symbols.sh - fail if a bare-metal image or object links floating point
# or heap allocation.
#   usage: sh tests/mcu/check-symbols.sh NM FILE...   (NM: e.g. arm-none-eabi-nm)
# Every symbol FILE defines or references is checked against
#  - the soft-float helpers: the ARM EABI ones (__aeabi_fadd, __aeabi_dmul,
#    __aeabi_i2f, __aeabi_ul2d, __aeabi_cdcmple, __aeabi_f2iz, ...) and libgcc's
#    generic ones (__adddf3, __mulsf3, __floatsidf, __fixdfsi, __extendsfdf2,
#    __truncdfsf2, __eqdf2, __unorddf2, ...), and the usual libm entry points;
#  - libc allocation: malloc, calloc, realloc, free (and newlib's reentrant
#    _malloc_r ...), memalign, aligned_alloc, _sbrk / sbrk.
# Prints the offending symbols and exits 1; exits 0 when there are none.
set -u
if [ $# -lt 2 ]; then
    echo "usage: $0 NM FILE..." >&2
    exit 2
fi
nm=$1
shift
float_re='^(__aeabi_([fd][a-z0-9]*|c[fd][a-z0-9]*|u?i2[fd]|u?l2[fd])|__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord|extend|trunc|fix|fixuns|float|floatun|pow|powi)[a-z]*(sf|df|tf|xf)[0-9]?|(sqrt|cbrt|sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|exp|exp2|expm1|log|log2|log10|log1p|pow|floor|ceil|trunc|round|lround|llround|rint|lrint|nearbyint|fabs|fmod|remainder|hypot|ldexp|frexp|modf|fmin|fmax|fma)[fl]?|_?(strtod|strtof|atof|_dtoa_r|__dtoa|_printf_float|_scanf_float))$'
alloc_re='^_?(malloc|calloc|realloc|reallocf|reallocarray|free|memalign|aligned_alloc|posix_memalign|valloc|pvalloc|_malloc_r|_calloc_r|_realloc_r|_free_r|_memalign_r|sbrk|_sbrk|_sbrk_r|__malloc_lock|_malloc_trim_r)$'
status=0
for f in "$@"; do
    syms=$("$nm" -A "$f" 2>/dev/null) || { echo "check-symbols: $nm cannot read $f" >&2; exit 2; }
    # "file:member: [addr] T name" -> name
    names=$(printf '%s\n' "$syms" | awk '{print $NF}' | sort -u)
    bad_float=$(printf '%s\n' "$names" | grep -E "$float_re")
    bad_alloc=$(printf '%s\n' "$names" | grep -E "$alloc_re")
    if [ -n "$bad_float" ]; then
        echo "check-symbols: $f links floating point:" $bad_float
        status=1
    fi
    if [ -n "$bad_alloc" ]; then
        echo "check-symbols: $f links heap allocation:" $bad_alloc
        status=1
    fi
done
exit $status
