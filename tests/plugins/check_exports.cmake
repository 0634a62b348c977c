# Fails unless every plugin in PLUGINS (a ';'-list of .so paths) exports exactly one
# defined dynamic symbol, clothlab_plugin_entry. Run with cmake -DNM=... -DPLUGINS=... -P.
foreach(plugin IN LISTS PLUGINS)
  execute_process(COMMAND "${NM}" -D --defined-only "${plugin}"
                  OUTPUT_VARIABLE symbols RESULT_VARIABLE failed)
  if(failed)
    message(FATAL_ERROR "${NM} failed on ${plugin}")
  endif()
  string(REGEX REPLACE "[^\n]* " "" names "${symbols}")
  string(STRIP "${names}" names)
  if(NOT names STREQUAL "clothlab_plugin_entry")
    message(FATAL_ERROR "${plugin} exports:\n${symbols}")
  endif()
endforeach()
