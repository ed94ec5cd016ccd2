# Warnings are errors on every target we own, host and ARM alike.
function(itp_enable_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wconversion -Wsign-conversion -Wshadow
    -Wdouble-promotion -Wcast-align -Wnon-virtual-dtor -Wold-style-cast
    -Wundef -Werror)
endfunction()

# The embedded rules for firmware_core and the target port: no exceptions,
# no RTTI, no thread-safe statics, and Eigen must never allocate.
function(itp_embedded_rules target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-fno-exceptions -fno-rtti -fno-threadsafe-statics>)
  target_compile_definitions(${target} PUBLIC EIGEN_NO_MALLOC)
endfunction()
