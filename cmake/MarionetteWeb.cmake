# The WebAssembly build (emscripten; scripts/build-web, docs/web.md).
#
# The dependencies left in it are header-only Debian packages under /usr/include. That
# folder cannot be an include path here (glibc's headers would shadow the sysroot's), so
# each one is linked into a folder of the build tree of its own and given as an imported
# target under the name the native build's find_package gives it.
if(NOT EMSCRIPTEN)
  message(FATAL_ERROR "MarionetteWeb.cmake is for the emscripten toolchain (scripts/build-web)")
endif()
foreach(_option ASSIMP TTS PRT RENDERER TRACKING)
  if(MARIONETTE_WITH_${_option})
    message(STATUS "web build: MARIONETTE_WITH_${_option} is native only; left out")
    set(MARIONETTE_WITH_${_option} OFF)
  endif()
endforeach()
set(MARIONETTE_BML_XML rapidxml CACHE STRING "BML's XML parser (pugixml is a binary-only Debian package)" FORCE)

set(_web_deps ${PROJECT_BINARY_DIR}/web-deps/include)
file(MAKE_DIRECTORY ${_web_deps})
foreach(_entry glm nlohmann tiny_gltf.h rapidxml)
  if(NOT EXISTS /usr/include/${_entry})
    message(FATAL_ERROR "web build: /usr/include/${_entry} is missing (scripts/setup --web installs it)")
  endif()
  if(NOT EXISTS ${_web_deps}/${_entry})
    file(CREATE_LINK /usr/include/${_entry} ${_web_deps}/${_entry} SYMBOLIC)
  endif()
endforeach()
function(_marionette_web_header_target name)
  add_library(${name} INTERFACE IMPORTED GLOBAL)
  set_property(TARGET ${name} PROPERTY INTERFACE_INCLUDE_DIRECTORIES ${_web_deps})
endfunction()
_marionette_web_header_target(glm::glm)
_marionette_web_header_target(nlohmann_json::nlohmann_json)
# tinygltf's implementation is compiled into the io module (io/src/web/); images are
# kept encoded by the importer's own loader, so stb_image is not needed.
_marionette_web_header_target(TinyGLTF::TinyGLTF)
set_property(TARGET TinyGLTF::TinyGLTF PROPERTY INTERFACE_COMPILE_DEFINITIONS TINYGLTF_NO_STB_IMAGE TINYGLTF_NO_STB_IMAGE_WRITE)
add_library(Threads::Threads INTERFACE IMPORTED GLOBAL)  # one thread: the scene runs its characters on the caller

# SIMD: the native SSE2 kernels, compiled to WebAssembly SIMD128 through emscripten's
# SSE headers (one source for both; docs/web.md gives the bits each build gives).
# Exceptions: the loaders report bad files by throwing inside the library; wasm's own
# exception handling costs nothing until something throws.
add_compile_options(-msimd128 -msse2 -fwasm-exceptions)
add_link_options(-fwasm-exceptions)
set(MARIONETTE_RAPIDXML_INCLUDE_DIR ${_web_deps} CACHE PATH "rapidxml, staged for the web build" FORCE)
