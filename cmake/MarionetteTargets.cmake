# Helpers for the project's own targets: warnings and the library pattern.
# Warnings for the project's own targets (not for the dependencies' headers).
function(marionette_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Wno-float-conversion
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)  # GCC 12 false positive on std::string concatenation (GCC bug 105329)
endfunction()

# marionette_library(<short name> SOURCES ... ) creates marionette_<name> with
# the alias marionette::<name>, its include/ folder, warnings and install rules.
function(marionette_library name)
  cmake_parse_arguments(L "" "" "SOURCES" ${ARGN})
  set(target marionette_${name})
  add_library(${target} ${L_SOURCES})
  add_library(marionette::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  marionette_warnings(${target})
  install(TARGETS ${target} EXPORT marionetteTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endfunction()

# marionette_link_private(<target> <dependency target> [NAMES library names...])
# A static library's private dependencies must reach whoever links it, but an installed
# package should not make its users find our dependencies' CMake packages (nor need
# their headers): the build tree links the dependency's target, the installed targets
# name its libraries (-lassimp ...), and header-only dependencies (no NAMES) vanish.
function(marionette_link_private target dependency)
  cmake_parse_arguments(P "" "" "NAMES" ${ARGN})
  target_link_libraries(${target} PRIVATE $<BUILD_INTERFACE:${dependency}>)
  foreach(name IN LISTS P_NAMES)
    target_link_libraries(${target} INTERFACE $<INSTALL_INTERFACE:${name}>)
  endforeach()
endfunction()
