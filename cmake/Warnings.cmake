# Warnings and sanitizers for our own targets (never for third-party code).
add_library(aal_warnings INTERFACE)
# -Wno-missing-field-initializers: the Vulkan idiom `VkXInfo info{sType}`
# value-initializes every other member on purpose.
target_compile_options(aal_warnings INTERFACE -Wall -Wextra -Wshadow
                                              -Wno-missing-field-initializers)
if(AAL_WERROR)
  target_compile_options(aal_warnings INTERFACE -Werror)
endif()
if(AAL_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(AAL_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "AAL_FUZZ=ON needs clang (libFuzzer): configure with "
                        "-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ (scripts/fuzz.sh)")
  endif()
  # Coverage for libFuzzer and ASan+UBSan on everything; fuzz/ links the
  # fuzzer's main into its targets.
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
