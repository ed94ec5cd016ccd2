# CTest driver: qp_solve on the 35 Maros-Meszaros QPs with n <= 150 (issue 15).
# The data lives beside the repository (../shared/data/maros-meszaros); when it
# is absent the test is skipped (exit code 77, SKIP_RETURN_CODE) with a message.
# Acceptance: >= 32 of 35 solved to 1e-6 relative objective, no 'optimal' that
# misses its published optimum, no 'infeasible'.
if(NOT IS_DIRECTORY "${DATA_DIR}")
  message("skipped: Maros-Meszaros data not found at ${DATA_DIR}")
  cmake_language(EXIT 77)
endif()
file(GLOB _files "${DATA_DIR}/*.QPS")
list(LENGTH _files _count)
if(_count EQUAL 0)
  message("skipped: no .QPS files in ${DATA_DIR}")
  cmake_language(EXIT 77)
endif()
list(SORT _files)
execute_process(COMMAND "${QP_SOLVE}" --references "${REFERENCES}" --require-solved ${REQUIRE} ${_files}
                RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "qp_solve: fewer than ${REQUIRE} of ${_count} solved, or a wrong optimal/infeasible")
endif()
