# The build id the firmware reports in its Pong: project version, git commit
# (when the tree is a git checkout) and the target it was built for.
find_package(Git QUIET)
set(_itp_commit "nogit")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --short=10 HEAD
                  WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
                  OUTPUT_VARIABLE _itp_head OUTPUT_STRIP_TRAILING_WHITESPACE
                  ERROR_QUIET RESULT_VARIABLE _itp_rc)
  if(_itp_rc EQUAL 0 AND _itp_head)
    set(_itp_commit "${_itp_head}")
  endif()
endif()
if(CMAKE_CROSSCOMPILING)
  set(_itp_where "${CMAKE_SYSTEM_PROCESSOR}")
else()
  set(_itp_where "host")
endif()
set(ITP_BUILD_ID "itplan-${PROJECT_VERSION}-${_itp_commit}-${_itp_where}")
message(STATUS "itplan build id: ${ITP_BUILD_ID}")
