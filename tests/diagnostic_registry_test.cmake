# The generated diagnostic registry (cmake/diagnostic_registry.cmake), on planted source trees
# under WORK: the list follows the `order` of each DAMPSYM_DIAGNOSTIC line (not the file names),
# one header may register two diagnostics, and each of the mistakes a newcomer can make stops the
# build with a message naming the header: no registration line, a malformed one, a type
# registered twice. Inputs: SCRIPT (the generator), WORK (a scratch directory).
cmake_minimum_required(VERSION 3.25)

function(plant tree file text)
  file(WRITE ${WORK}/${tree}/src/diagnostics/${file} "${text}")
endfunction()

function(generate tree out_rc out_msg)
  execute_process(COMMAND ${CMAKE_COMMAND} -DSRC_DIR=${WORK}/${tree} -DOUT=${WORK}/${tree}/out.hpp
                          -P ${SCRIPT}
                  RESULT_VARIABLE rc ERROR_VARIABLE msg OUTPUT_QUIET)
  set(${out_rc} ${rc} PARENT_SCOPE)
  set(${out_msg} "${msg}" PARENT_SCOPE)
endfunction()

function(expect_failure tree needle)
  generate(${tree} rc msg)
  if(rc EQUAL 0)
    message(FATAL_ERROR "${tree}: the generator accepted it")
  endif()
  string(REGEX REPLACE "[ \n]+" " " msg "${msg}") # CMake wraps its messages
  string(FIND "${msg}" "${needle}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${tree}: the message does not say '${needle}':\n${msg}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK})
plant(good a_diagnostic.hpp "struct ADiagnostic {};\nDAMPSYM_DIAGNOSTIC(ADiagnostic, 30);\n")
plant(good b_diagnostic.hpp # indented or not; a commented-out line is not a registration
      "    DAMPSYM_DIAGNOSTIC(BDiagnostic, 10);\nDAMPSYM_DIAGNOSTIC(B2Diagnostic, 20);\n// DAMPSYM_DIAGNOSTIC(Old, 5);\n")
plant(good helper.hpp "DAMPSYM_DIAGNOSTIC(NotADiagnostic, 1);\n") # not a *_diagnostic.hpp
generate(good rc msg)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "good: ${msg}")
endif()
file(READ ${WORK}/good/out.hpp out)
if(NOT out MATCHES "BDiagnostic, \\\\\n    B2Diagnostic, \\\\\n    ADiagnostic\n")
  message(FATAL_ERROR "good: not listed by order:\n${out}")
endif()
if(NOT out MATCHES "#include \"diagnostics/b_diagnostic.hpp\"\n#include \"diagnostics/a_diagnostic.hpp\"\n\n")
  message(FATAL_ERROR "good: the headers are not included once each, by order:\n${out}")
endif()
if(out MATCHES "NotADiagnostic")
  message(FATAL_ERROR "good: a header other than *_diagnostic.hpp was read:\n${out}")
endif()
# Rewritten only when the list changes (an unchanged tree recompiles nothing).
file(TIMESTAMP ${WORK}/good/out.hpp before "%s")
execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1.1)
generate(good rc msg)
file(TIMESTAMP ${WORK}/good/out.hpp after "%s")
if(NOT before STREQUAL after)
  message(FATAL_ERROR "good: an unchanged list was written again")
endif()

plant(missing a_diagnostic.hpp "struct ADiagnostic {};\n")
expect_failure(missing "src/diagnostics/a_diagnostic.hpp: no `DAMPSYM_DIAGNOSTIC(Type, order);` line")
plant(malformed a_diagnostic.hpp "DAMPSYM_DIAGNOSTIC(ADiagnostic);\n")
expect_failure(malformed "src/diagnostics/a_diagnostic.hpp: 'DAMPSYM_DIAGNOSTIC(ADiagnostic);' is not")
plant(twice a_diagnostic.hpp "DAMPSYM_DIAGNOSTIC(ADiagnostic, 1);\n")
plant(twice b_diagnostic.hpp "DAMPSYM_DIAGNOSTIC(ADiagnostic, 2);\n")
expect_failure(twice "ADiagnostic is registered twice")
message(STATUS "diagnostic registry: ordered list, rewritten only on change, 3 planted mistakes refused")
