# The project's floating-point mode, stated once for every target.
#
# A run must give bit-identical numbers in every process: the coordinator and its workers are matched on the
# build's fingerprint (common/program/build_fingerprint.h), which records this mode. So nothing may depend on what a
# compiler or machine would pick by default:
#   -ffp-contract=off   no a*b+c contracted into one FMA (GCC contracts by default in GNU mode when it can)
#   -fno-fast-math      IEEE semantics: no reassociation, no flush-to-zero, NaN and -0 kept
#   x86_64: -march=x86-64 -mtune=generic -mfpmath=sse   baseline ISA: SSE2 doubles (no x87 excess precision),
#                                                        no FMA instructions, whatever the build machine has
# On other processors the ISA is left to the compiler; fp-contract is still off.
set(POET_FLOAT_FLAGS -ffp-contract=off -fno-fast-math)
if(CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  list(APPEND POET_FLOAT_FLAGS -march=x86-64 -mtune=generic -mfpmath=sse)
endif()
list(JOIN POET_FLOAT_FLAGS " " POET_FLOAT_MODE)

add_compile_options(${POET_FLOAT_FLAGS})
# The same description as text, so that code can print it (build_fingerprint(), benchmark context).
add_compile_definitions(POET_FLOAT_MODE="${POET_FLOAT_MODE}")
message(STATUS "poet float mode: ${POET_FLOAT_MODE}")
