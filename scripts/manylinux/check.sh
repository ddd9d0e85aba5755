#!/usr/bin/env bash
# Lists what a built module or wheel asks of the system and fails when it is
# more than manylinux_2_28 allows: the GLIBC_/GLIBCXX_ symbol versions, the
# libraries it needs (NEEDED), and undefined symbols that are neither
# versioned C library ones nor CPython's (those fail only at import, as
# libomp 16's missing __kmpc_dispatch_deinit did).
#   scripts/manylinux/check.sh FILE.so|FILE.whl...
set -euo pipefail
status=0
for file in "$@"; do
  modules=("$file")
  if [[ $file == *.whl ]]; then
    unpacked=$(mktemp -d)
    python3 -m zipfile -e "$file" "$unpacked"
    mapfile -t modules < <(find "$unpacked" -name '*.so*' -type f)
  fi
  for so in "${modules[@]}"; do
    glibc=$(objdump -T "$so" | { grep -o 'GLIBC_[0-9.]*' || true; } | sort -uV | tail -n 1)
    glibcxx=$(objdump -T "$so" | { grep -o 'GLIBCXX_[0-9.]*' || true; } | sort -uV | tail -n 1)
    needed=$(objdump -p "$so" | awk '/NEEDED/ { printf "%s ", $2 }')
    undefined=$(objdump -T "$so" | awk '/\*UND\*/ && !/GLIBC_/ { print $NF }' |
                grep -vE '^(_?Py|PyInit|__gmon_start__|_ITM_|__cxa_finalize)' | grep -v '^$' || true)
    echo "$(basename "$file")$([ "$so" = "$file" ] || echo ": $(basename "$so")"): highest ${glibc:-no GLIBC}, ${glibcxx:-no GLIBCXX}; NEEDED $needed"
    if [ -n "$glibc" ] && [ "$(printf '%s\nGLIBC_2.28\n' "$glibc" | sort -V | tail -n 1)" != GLIBC_2.28 ]; then
      echo "  needs $glibc, above manylinux_2_28's GLIBC_2.28" >&2; status=1
    fi
    [ -z "$glibcxx" ] || { echo "  needs the system's libstdc++ ($glibcxx)" >&2; status=1; }
    for lib in $needed; do
      case $lib in libc.so.6|libm.so.6|libpthread.so.0|libdl.so.2|ld-linux-x86-64.so.2|librt.so.1) ;;
        *) echo "  needs $lib, not part of manylinux_2_28" >&2; status=1 ;; esac
    done
    [ -z "$undefined" ] || { echo "  undefined, not libc or CPython: $undefined" >&2; status=1; }
  done
done
exit $status
