# Warnings for the project's own targets (not for the dependencies' headers).
function(marionette_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Wno-float-conversion
    -Wno-restrict)  # GCC 12 false positive on std::string concatenation (GCC bug 105329)
endfunction()
