# cmake -DPROGRAM=TEST_PROGRAM -DTESTS=Suite.Test:Suite.Test -DWORK=DIR -P compare_digests.cmake
# Runs the GoogleTest program twice, in two processes, on the tests named in TESTS (a gtest
# filter without wildcards), each run with MARIONETTE_DIGEST_DIR set to a folder of its own
# (determinism_digest.hpp), and fails unless both runs pass and every test wrote the same
# digest in both.
cmake_minimum_required(VERSION 3.20)
foreach(var PROGRAM TESTS WORK)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "compare_digests.cmake: ${var} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")  # nothing from an earlier run can stand in for this one's
foreach(run first second)
  file(MAKE_DIRECTORY "${WORK}/${run}")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env "MARIONETTE_DIGEST_DIR=${WORK}/${run}"
                          "${PROGRAM}" "--gtest_filter=${TESTS}"
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT status STREQUAL "0")
    message(FATAL_ERROR "${run} run failed (exit status '${status}'):\n${out}")
  endif()
endforeach()
string(REPLACE ":" ";" tests "${TESTS}")
foreach(test IN LISTS tests)
  foreach(run first second)
    if(NOT EXISTS "${WORK}/${run}/${test}.digest")
      message(FATAL_ERROR "${test} wrote no digest in the ${run} run (does it call recordDigest()?)")
    endif()
    file(READ "${WORK}/${run}/${test}.digest" digest_${run})
  endforeach()
  if(NOT digest_first STREQUAL digest_second)
    message(FATAL_ERROR "${test} differs between two processes:\n  ${digest_first}  ${digest_second}")
  endif()
  string(STRIP "${digest_first}" shown)
  message(STATUS "${test}: ${shown} in both processes")
endforeach()
