# Warning flags, SIMD selection and the opt-in -march=native, as an interface target that every
# ldsm target links privately.
add_library(ldsm_build_flags INTERFACE)
target_compile_options(ldsm_build_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic>
  $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>
  $<$<CXX_COMPILER_ID:Clang>:-Wshadow-uncaptured-local>
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
                                 -Wnull-dereference>)
if(LDSM_WERROR)
  target_compile_options(ldsm_build_flags INTERFACE $<$<CXX_COMPILER_ID:GNU,Clang>:-Werror>)
endif()
if(LDSM_NATIVE)
  target_compile_options(ldsm_build_flags INTERFACE -march=native)
endif()
# No fused multiply-adds the source does not write: GCC contracts a + b * c into one instruction
# where the processor has it (always on ARM, on x86-64 only with -march=native), which rounds once
# instead of twice. ldsm's SIMD kernels must equal their scalar references exactly (the depth
# search's best match must not depend on the instruction set), and results should agree across
# machines as far as the libraries allow (docs/determinism.md). The x86-64 baseline has no FMA, so
# this changes nothing there.
target_compile_options(ldsm_build_flags INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-ffp-contract=off>)

# Resolve LDSM_SIMD=auto to the instruction set of the target processor.
set(LDSM_SIMD_RESOLVED ${LDSM_SIMD})
if(LDSM_SIMD STREQUAL "auto")
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64|i[3-6]86)$")
    set(LDSM_SIMD_RESOLVED sse)
  elseif(CMAKE_SYSTEM_PROCESSOR MATCHES "^(aarch64|arm64|armv7.*|arm)$")
    set(LDSM_SIMD_RESOLVED neon)
  else()
    set(LDSM_SIMD_RESOLVED scalar)
  endif()
endif()
if(NOT LDSM_SIMD_RESOLVED MATCHES "^(sse|neon|scalar)$")
  message(FATAL_ERROR "LDSM_SIMD must be auto, sse, neon or scalar (got '${LDSM_SIMD}')")
endif()
message(STATUS "ldsm: SIMD kernels: ${LDSM_SIMD_RESOLVED}")
install(TARGETS ldsm_build_flags EXPORT ldsmTargets)
