#!/usr/bin/env bash
# OpenCL without a vendored loader: a static stub (opencl_stub.py) that
# dlopen()s the system's libOpenCL.so.1 on first use, so the module loads
# where no OpenCL is installed and says why there is no device. (Debian's
# ocl-icd source is not on the mirror, and a wheel should use the system's
# ICD loader anyway: it is what finds the drivers.)
set -euo pipefail
d=$OBJ/opencl && mkdir -p "$d"
/usr/bin/python3 "$(dirname "$0")/../opencl_stub.py" /usr/include/CL/cl.h "$d/opencl_stub.c"
"$CC" -O2 -fPIC -c "$d/opencl_stub.c" -o "$d/opencl_stub.o"
rm -f "$PREFIX/lib/libOpenCL.a" && "$AR" rcs "$PREFIX/lib/libOpenCL.a" "$d/opencl_stub.o"
