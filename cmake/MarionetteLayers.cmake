# The project's layers (docs/architecture.md): every module, inside the middleware and out
# of it (prt, tts_espeak, bml, bridge, the C API, the AR example's parts, the CLI), is
# declared once with the layers it uses. Its target then sees the include folders of
# those layers (and theirs) and no other: an #include of a layer above or beside it does
# not find the file, so the build itself refuses a backward dependency.
# tests/architecture/check_layers.cmake checks the declarations against the code.
#
# marionette_layer(<name> [TARGET <target>] ROOT <folders of its files...>
#                  [INCLUDE <include root>] [HEADERS <header files or folders...>]
#                  [USES <lower layers...>])
#   TARGET   the library or program built from it; gets the USES' include folders:
#            a middleware module's headers (marionette_mw_<m>_headers) with the middleware's
#            objects linked (LINK_ONLY: the one library an engine links), or another
#            layer's target.
#   HEADERS  what other layers may include (folders: every *.h / *.hpp in them); none for
#            a program.
# Layers are declared lowest first: USES may only name layers declared before, so the
# layer graph has no cycle.

function(marionette_layer name)
  cmake_parse_arguments(L "" "TARGET;INCLUDE" "ROOT;HEADERS;USES" ${ARGN})
  get_property(known GLOBAL PROPERTY MARIONETTE_LAYERS)
  if(name IN_LIST known)
    message(FATAL_ERROR "layer '${name}' is declared twice")
  endif()
  foreach(u IN LISTS L_USES)
    if(NOT u IN_LIST known)
      message(FATAL_ERROR "layer '${name}' uses '${u}', which is not declared before it (layers go lowest first)")
    endif()
  endforeach()
  set(headers "")
  foreach(h IN LISTS L_HEADERS)
    if(IS_DIRECTORY ${h})
      file(GLOB found CONFIGURE_DEPENDS ${h}/*.h ${h}/*.hpp)
      list(APPEND headers ${found})
    else()
      list(APPEND headers ${h})
    endif()
  endforeach()
  set_property(GLOBAL APPEND PROPERTY MARIONETTE_LAYERS ${name})
  set_property(GLOBAL PROPERTY MARIONETTE_LAYER_${name}_ROOT "${L_ROOT}")
  set_property(GLOBAL PROPERTY MARIONETTE_LAYER_${name}_INCLUDE "${L_INCLUDE}")
  set_property(GLOBAL PROPERTY MARIONETTE_LAYER_${name}_HEADERS "${headers}")
  set_property(GLOBAL PROPERTY MARIONETTE_LAYER_${name}_USES "${L_USES}")
  set_property(GLOBAL PROPERTY MARIONETTE_LAYER_${name}_TARGET "${L_TARGET}")
  if(NOT L_TARGET OR name IN_LIST MARIONETTE_MIDDLEWARE_MODULES)
    return()  # a middleware module links its own (middleware/CMakeLists.txt)
  endif()
  marionette_use_layers(${L_TARGET} ${L_USES})
endfunction()

# marionette_use_layers(<target> <layers...>): what marionette_layer does for its TARGET,
# for another target built from the same layer (the C API's shared library with espeak-ng).
function(marionette_use_layers target)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "EXECUTABLE" OR type STREQUAL "SHARED_LIBRARY")  # a shared library hides what it uses
    set(scope PRIVATE)
  elseif(type STREQUAL "INTERFACE_LIBRARY")
    set(scope INTERFACE)
  else()
    set(scope PUBLIC)
  endif()
  set(middleware FALSE)
  foreach(u IN LISTS ARGN)
    if(TARGET marionette_mw_${u}_headers)
      target_link_libraries(${target} ${scope} $<BUILD_INTERFACE:marionette_mw_${u}_headers>)
      set(middleware TRUE)
    else()
      get_property(t GLOBAL PROPERTY MARIONETTE_LAYER_${u}_TARGET)
      if(t)
        target_link_libraries(${target} ${scope} ${t})
      endif()
    endif()
  endforeach()
  if(middleware)
    # The objects: in the build tree marionette_middleware has no include folder (the
    # modules' headers come from the _headers targets above); installed, it is
    # marionette::middleware with the whole package's headers.
    target_link_libraries(${target} ${scope} marionette_middleware)
  endif()
endfunction()

# Writes what tests/architecture/check_layers.cmake reads: per layer its root, headers, the
# include folders its target really compiles with, what it uses, and everything below it.
# Called once, after every layer is declared.
function(marionette_write_layers file)
  get_property(layers GLOBAL PROPERTY MARIONETTE_LAYERS)
  set(text "set(LAYERS ${layers})\n")
  foreach(l IN LISTS layers)
    foreach(p ROOT INCLUDE HEADERS USES TARGET)
      get_property(v GLOBAL PROPERTY MARIONETTE_LAYER_${l}_${p})
      string(APPEND text "set(${p}_${l} \"${v}\")\n")
    endforeach()
    # Everything below it, transitively: what it may include.
    set(seen ${l})
    set(todo ${l})
    while(todo)
      list(POP_FRONT todo x)
      get_property(uses GLOBAL PROPERTY MARIONETTE_LAYER_${x}_USES)
      foreach(u IN LISTS uses)
        if(NOT u IN_LIST seen)
          list(APPEND seen ${u})
          list(APPEND todo ${u})
        endif()
      endforeach()
    endwhile()
    string(APPEND text "set(ALLOWED_${l} ${seen})\n")
    get_property(t GLOBAL PROPERTY MARIONETTE_LAYER_${l}_TARGET)
    if(t)
      get_target_property(type ${t} TYPE)
      if(type STREQUAL "INTERFACE_LIBRARY")
        set(dirs "$<TARGET_PROPERTY:${t},INTERFACE_INCLUDE_DIRECTORIES>")
      else()
        set(dirs "$<TARGET_PROPERTY:${t},INCLUDE_DIRECTORIES>")
      endif()
      string(APPEND text "set(DIRS_${l} \"$<REMOVE_DUPLICATES:${dirs}>\")\n")
    endif()
  endforeach()
  file(GENERATE OUTPUT ${file} CONTENT "${text}")
endfunction()
