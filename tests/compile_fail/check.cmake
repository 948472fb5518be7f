# Compiles SOURCE and passes only if compilation fails with a message matching the regex
# given in the source as `// expect-error: REGEX` (or succeeds, for a source without one).
file(STRINGS ${SOURCE} expect REGEX "// expect-error: ")
string(REGEX REPLACE ".*// expect-error: " "" expect "${expect}")
execute_process(COMMAND ${CXX} -std=c++20 -fsyntax-only -I${INCLUDE} -I${EIGEN} ${SOURCE}
                RESULT_VARIABLE rc ERROR_VARIABLE err OUTPUT_QUIET)
if(expect STREQUAL "")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "control source failed to compile:\n${err}")
  endif()
elseif(rc EQUAL 0)
  message(FATAL_ERROR "${SOURCE} compiled, but must fail with: ${expect}")
elseif(NOT err MATCHES "${expect}")
  message(FATAL_ERROR "${SOURCE} failed for another reason than '${expect}':\n${err}")
endif()
