# A documented table comes from the current build (issue 41): runs the program that makes it,
# then compares the fresh table with the committed one (tests/support/compare_table.py), every
# column but the run times.
#   cmake -DPROGRAM=exe -DARGS="a|b" -DWORK=dir -DCOMMITTED=docs/data/x.md -DIGNORE="col|col"
#         -DPYTHON=python3 -DCOMPARE=tests/support/compare_table.py -P check_documented_table.cmake
# ('|' separates the lists: add_test would split a ';' list into separate arguments. WORKDIR in
# ARGS is replaced by WORK.)
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
string(REPLACE "WORKDIR" "${WORK}" ARGS "${ARGS}")
string(REPLACE "|" ";" ARGS "${ARGS}")
string(REPLACE "|" ";" IGNORE "${IGNORE}")
execute_process(COMMAND "${PROGRAM}" ${ARGS} OUTPUT_FILE "${WORK}/fresh.md" ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${PROGRAM} failed (${rc}):\n${err}")
endif()
set(ignore)
foreach(column IN LISTS IGNORE)
  list(APPEND ignore --ignore "${column}")
endforeach()
execute_process(COMMAND "${PYTHON}" "${COMPARE}" "${WORK}/fresh.md" "${COMMITTED}" ${ignore} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${COMMITTED} does not come from the current build (regenerate it: scripts/accuracy)")
endif()
