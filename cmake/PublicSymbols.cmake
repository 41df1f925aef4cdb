# The shared library exports exactly the public API: every nbrdf_* function declared in
# include/nbrdf/*.h. Internal functions carry their layer's prefix (core_, nn_, model_, ...),
# but a name pattern would still let a stray nbrdf_ helper out; the list is read from the
# public headers instead, and cmake re-runs when a public header changes.
function(nbrdf_public_symbols_map out_file)
  file(GLOB headers ${PROJECT_SOURCE_DIR}/include/nbrdf/*.h)
  set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${headers})
  set(names)
  foreach(h IN LISTS headers)
    file(READ ${h} text)
    # Drop comments, so a function named in a header's prose or example is not exported.
    string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
    string(REGEX MATCHALL "nbrdf_[a-z0-9_]+[ \t\r\n]*\\(" calls "${text}")
    foreach(c IN LISTS calls)
      string(REGEX REPLACE "[ \t\r\n]*\\($" "" c "${c}")
      list(APPEND names ${c})
    endforeach()
  endforeach()
  list(REMOVE_DUPLICATES names)
  list(SORT names)
  list(LENGTH names count)
  string(JOIN ";\n    " body ${names})
  file(CONFIGURE OUTPUT ${out_file} CONTENT "NBRDF_0 {\n  global:\n    ${body};\n  local: *;\n};\n")
  set(NBRDF_PUBLIC_SYMBOL_COUNT ${count} PARENT_SCOPE)
endfunction()
