# Writes a header holding one text file as a raw string literal, so that a library needs no
# data file at run time:  cmake -DIN=file -DOUT=header -DNAME=kVariable -DNAMESPACE=ns -P embed_text.cmake
file(READ ${IN} _text)
get_filename_component(_name ${IN} NAME)
set(_body "// Generated from ${_name} by cmake/embed_text.cmake; do not edit.\n#pragma once\n#include <string_view>\n\nnamespace ${NAMESPACE} {\ninline constexpr std::string_view ${NAME} = R\"embedded(${_text})embedded\";\n}  // namespace ${NAMESPACE}\n")
file(WRITE ${OUT}.tmp "${_body}")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different ${OUT}.tmp ${OUT})
