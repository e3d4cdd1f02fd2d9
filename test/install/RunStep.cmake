# run(STEP COMMAND...): runs COMMAND, prints what it printed under STEP, and fails the script if it fails. Shared by
# the install tests' scripts.
function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message(STATUS "${step}:\n${out}${err}")
  if(NOT code STREQUAL "0")
    message(FATAL_ERROR "${step} failed (${code})")
  endif()
endfunction()
