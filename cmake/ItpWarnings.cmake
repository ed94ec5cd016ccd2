# Warnings are errors on every target we own, host and ARM alike.
function(itp_enable_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
    -Wdouble-promotion -Wcast-align -Wnon-virtual-dtor -Wold-style-cast
    -Wundef -Werror)
endfunction()

# The embedded rules for firmware_core and the target port: no exceptions,
# no RTTI, no thread-safe statics, and Eigen must never allocate. No fused
# multiply-add contraction either: the Cortex-M7 has FMA and x86-64 (baseline)
# does not, and the host and target must compute the same roundings.
function(itp_embedded_rules target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti -fno-threadsafe-statics -ffp-contract=off>)
  target_compile_definitions(${target} PUBLIC EIGEN_NO_MALLOC)
endfunction()
