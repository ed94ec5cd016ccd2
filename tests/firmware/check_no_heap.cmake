# Fails if the firmware ELF links any allocator symbol. Run with
#   cmake -DNM=arm-none-eabi-nm -DELF=path/to.elf -P check_no_heap.cmake
execute_process(COMMAND ${NM} -C ${ELF} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${ELF}")
endif()
string(REGEX MATCHALL "[^\n]*( malloc| free| calloc| realloc| _malloc_r| _free_r|operator new|operator delete)[^\n]*" hits "${symbols}")
if(hits)
  message(FATAL_ERROR "firmware links allocator symbols:\n${hits}")
endif()
message(STATUS "no malloc, free, operator new or operator delete in ${ELF}")
