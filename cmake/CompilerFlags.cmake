# Warnings for our own targets; optimisation comes from the build type (Release by default).
function(meshsmith_set_warnings target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter -Wno-deprecated-copy
                                             -Wno-class-memaccess -Wno-maybe-uninitialized)
  endif()
endfunction()
