# The middleware's layers hold (cmake -P; tests/CMakeLists.txt passes the arguments):
#   1. each module's public headers preprocess with only its own include folder and those
#      of the modules below it (a header that reaches up fails here as it would in a build);
#   2. a header of any module above or beside a module is NOT found from it: the build
#      itself rejects a backward #include (the positive control in 1 shows the same
#      command finds what is allowed);
#   3. no middleware source reaches another module's files by a relative path ("../").
# Arguments: -DCXX=compiler -DROOT=middleware folder -DLAYERS=file (written at configure
# time: one "set(ALLOWED_<module> ...)" per module, itself and everything below it).
include(${LAYERS})
set(failures "")
set(checks 0)
set(snippet ${CMAKE_CURRENT_BINARY_DIR}/layer_check.cpp)
function(preprocess module header result out)
  set(flags "")
  foreach(m IN LISTS ALLOWED_${module})
    list(APPEND flags -I${ROOT}/${m}/include)
  endforeach()
  file(WRITE ${snippet} "#include \"${header}\"\n")
  execute_process(COMMAND ${CXX} -std=c++20 -E -o /dev/null ${flags} ${snippet}
                  RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
  set(${result} ${rc} PARENT_SCOPE)
  set(${out} "${err}" PARENT_SCOPE)
endfunction()

foreach(module IN LISTS MODULES)
  # 1. its own headers, with what it may see
  file(GLOB headers RELATIVE ${ROOT}/${module}/include ${ROOT}/${module}/include/marionette/${module}/*.hpp)
  foreach(h IN LISTS headers)
    preprocess(${module} ${h} rc err)
    math(EXPR checks "${checks} + 1")
    if(NOT rc EQUAL 0)
      string(REGEX MATCH "[^\n]*fatal error[^\n]*" why "${err}")
      list(APPEND failures "${module}: its header ${h} reaches outside its layers: ${why}")
    endif()
  endforeach()
  # 2. one header of each module it must not see
  foreach(other IN LISTS MODULES)
    list(FIND ALLOWED_${module} ${other} allowed)
    if(NOT allowed EQUAL -1)
      continue()
    endif()
    file(GLOB theirs RELATIVE ${ROOT}/${other}/include ${ROOT}/${other}/include/marionette/${other}/*.hpp)
    list(GET theirs 0 h)
    preprocess(${module} ${h} rc err)
    math(EXPR checks "${checks} + 1")
    if(rc EQUAL 0)
      list(APPEND failures "${module} can include ${h} of ${other}, a module that is not below it")
    elseif(NOT err MATCHES "No such file")
      list(APPEND failures "${module} including ${h}: failed for another reason than a missing file: ${err}")
    endif()
  endforeach()
  # 3. no relative reach into another module
  file(GLOB_RECURSE files ${ROOT}/${module}/*.cpp ${ROOT}/${module}/*.hpp)
  foreach(f IN LISTS files)
    file(STRINGS ${f} lines REGEX "^#include \"\\.\\./")
    math(EXPR checks "${checks} + 1")
    if(lines)
      list(APPEND failures "${f}: includes by a relative path: ${lines}")
    endif()
  endforeach()
endforeach()
list(LENGTH failures n)
if(n GREATER 0)
  list(JOIN failures "\n  " text)
  message(FATAL_ERROR "middleware layers: ${n} problem(s) in ${checks} checks:\n  ${text}")
endif()
list(JOIN MODULES " < " order)
message(STATUS "middleware layers hold: ${checks} checks over ${order}")
