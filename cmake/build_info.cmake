# Writes OUT from TEMPLATE with the source tree's git commit and whether it is dirty. Run by the
# dampsym_build_info target on every build (cmake -P), so the report's provenance describes the
# tree that was compiled, not the one that was configured; configure_file rewrites OUT only when
# its content changes, so an unchanged tree recompiles nothing.
# Inputs: SRC_DIR, TEMPLATE, OUT (and the @-variables of TEMPLATE passed with -D).
set(DAMPSYM_GIT_COMMIT "unknown")
set(DAMPSYM_GIT_DIRTY "unknown")
find_program(_git git)
if(_git)
  execute_process(COMMAND ${_git} -C ${SRC_DIR} rev-parse HEAD RESULT_VARIABLE _rc
                  OUTPUT_VARIABLE _commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(_rc EQUAL 0)
    set(DAMPSYM_GIT_COMMIT "${_commit}")
    # Tracked files only: the build directories and reports are not part of the source.
    execute_process(COMMAND ${_git} -C ${SRC_DIR} status --porcelain --untracked-files=no
                    RESULT_VARIABLE _rc OUTPUT_VARIABLE _status ERROR_QUIET)
    if(_rc EQUAL 0)
      if(_status STREQUAL "")
        set(DAMPSYM_GIT_DIRTY "false")
      else()
        set(DAMPSYM_GIT_DIRTY "true")
      endif()
    endif()
  endif()
endif()
configure_file(${TEMPLATE} ${OUT} @ONLY)
