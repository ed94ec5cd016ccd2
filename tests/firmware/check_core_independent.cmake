# Fails if any firmware_core source includes a port header or a platform
# header that would tie it to one target. Run with
#   cmake -DCORE_DIR=path/to/firmware_core -P check_core_independent.cmake
file(GLOB_RECURSE sources ${CORE_DIR}/*.hpp ${CORE_DIR}/*.cpp ${CORE_DIR}/*.h)
set(bad "")
foreach(src ${sources})
  file(STRINGS ${src} lines REGEX "#include *[<\"](port/|unistd|fcntl|poll|pthread|sys/|windows)")
  if(lines)
    list(APPEND bad "${src}: ${lines}")
  endif()
endforeach()
if(bad)
  string(REPLACE ";" "\n" bad "${bad}")
  message(FATAL_ERROR "firmware_core includes platform headers:\n${bad}")
endif()
list(LENGTH sources n)
message(STATUS "${n} firmware_core files checked: no port or platform includes")
