# Instruction-set level of the build (VID_ARCH).
#
# The filter's hot loops are small dense Eigen products (rank-3 covariance updates, 2x6 block
# Jacobians times covariance slices). With AVX2 + FMA Eigen uses 4-wide fused packets and these
# run 1.5-2.5x faster than with the x86-64 baseline (SSE2), which is what the per-update time
# targets of the estimator need. -march=x86-64-v3 (AVX2, FMA, BMI2; no AVX-512) is a standard
# micro-architecture level, so the binaries run on any x86-64 CPU of the last decade.
#
#   VID_ARCH=auto      (default) x86-64-v3 when the compiler accepts it and this machine runs it,
#                      baseline otherwise (a message says which)
#   VID_ARCH=x86-64-v3 force it;  VID_ARCH=baseline  never add -march
#
# The flag is added to every target of the project so that all code sharing Eigen types agrees
# on their alignment; the installed libraries carry it as a usage requirement, so a project that
# links them compiles its Eigen code the same way (mixed alignment crashes at run time). Third-party libraries (Ceres) are only called through double* interfaces.
set(VID_ARCH "auto" CACHE STRING "Instruction-set level: auto | x86-64-v3 | baseline")
set_property(CACHE VID_ARCH PROPERTY STRINGS auto x86-64-v3 baseline)

if(VID_ARCH STREQUAL "auto")
  include(CheckCXXSourceRuns)
  set(CMAKE_REQUIRED_FLAGS "-march=x86-64-v3")
  check_cxx_source_runs([=[
    int main() {
      __builtin_cpu_init();
      return (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
              __builtin_cpu_supports("bmi2")) ? 0 : 1;
    }]=] VID_HOST_RUNS_X86_64_V3)
  unset(CMAKE_REQUIRED_FLAGS)
  if(VID_HOST_RUNS_X86_64_V3)
    set(VID_ARCH_RESOLVED "x86-64-v3")
  else()
    set(VID_ARCH_RESOLVED "baseline")
  endif()
elseif(VID_ARCH STREQUAL "x86-64-v3" OR VID_ARCH STREQUAL "baseline")
  set(VID_ARCH_RESOLVED "${VID_ARCH}")
else()
  message(FATAL_ERROR "VID_ARCH must be auto, x86-64-v3 or baseline (got '${VID_ARCH}')")
endif()

set(VID_ARCH_FLAGS "")
if(VID_ARCH_RESOLVED STREQUAL "x86-64-v3")
  set(VID_ARCH_FLAGS -march=x86-64-v3)
  add_compile_options(${VID_ARCH_FLAGS})
  # GCC 12 flags Eigen's 4-wide loads of 3-vectors (guarded by a size check it does not
  # follow) as out of bounds: a known false positive of -Warray-bounds with AVX.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    list(APPEND VID_WARNINGS -Wno-array-bounds)
  endif()
endif()
message(STATUS "VID_ARCH=${VID_ARCH}: building for ${VID_ARCH_RESOLVED}")
