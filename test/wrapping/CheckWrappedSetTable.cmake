# cmake -DTABLE=<generated table> -DDOCUMENT=docs/wrapping.md -P CheckWrappedSetTable.cmake
# Fails unless the document holds the table of the wrapped set that GenerateWrappedSetTest.cmake wrote, verbatim.
file(READ "${TABLE}" table)
file(READ "${DOCUMENT}" document)
string(FIND "${document}" "${table}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${DOCUMENT} does not hold the table of the wrapped set; after a change of wrapping/, replace "
                      "its table with this one (${TABLE}):\n${table}")
endif()
message(STATUS "${DOCUMENT} holds the table of the wrapped set")
