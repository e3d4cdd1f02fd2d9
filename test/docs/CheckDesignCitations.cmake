# Fails, listing them, on design citations that do not resolve:
# - a citation of the outside design file the project started from (its name in capitals, with ".md" or followed by
#   "section N"): the project's own account is docs/design.md, and citations name it;
# - a citation "docs/design.md section N" (or "sections N, M and K"; the words may be split across comment lines)
#   whose section N has no heading "## N. ..." in docs/design.md;
# - inside docs/design.md, a "section N" (not "section N.M", the paper's numbering) with no such heading;
# - section headings of docs/design.md that are not numbered 1, 2, 3, ... in order.
#   cmake -DGIT=git -DSOURCE_DIR=<repository> -P CheckDesignCitations.cmake
# The files: every file git lists in SOURCE_DIR (tracked, and new files not ignored), text or binary (a binary file is
# read as the strings of text it holds); without git (a source tarball), every file under the project's directories
# and its top-level files. Nothing is skipped.
cmake_minimum_required(VERSION 3.16)
if(NOT DEFINED SOURCE_DIR)
  message(FATAL_ERROR "CheckDesignCitations.cmake needs -DSOURCE_DIR=...")
endif()

# The design's headings.
set(design "${SOURCE_DIR}/docs/design.md")
if(NOT EXISTS "${design}")
  message(FATAL_ERROR "${design} does not exist: the citations of docs/design.md have nothing to point to")
endif()
file(STRINGS "${design}" headings REGEX "^## [0-9]+\\. ")
set(sections "")
set(expected 1)
foreach(heading IN LISTS headings)
  string(REGEX REPLACE "^## ([0-9]+)\\. .*$" "\\1" headingNumber "${heading}")
  if(NOT headingNumber EQUAL expected)
    message(FATAL_ERROR "docs/design.md: the heading '${heading}' should be section ${expected}: sections are "
                        "numbered 1, 2, 3, ... in order, and the code cites them by number")
  endif()
  list(APPEND sections ${headingNumber})
  math(EXPR expected "${expected} + 1")
endforeach()
list(LENGTH sections numberOfSections)
if(numberOfSections EQUAL 0)
  message(FATAL_ERROR "docs/design.md has no section heading '## N. ...'")
endif()

# The files.
set(files "")
if(GIT AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT}" ls-files --cached --others --exclude-standard WORKING_DIRECTORY "${SOURCE_DIR}"
                  RESULT_VARIABLE result OUTPUT_VARIABLE listed ERROR_VARIABLE error)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "git ls-files failed in ${SOURCE_DIR}: ${error}")
  endif()
  string(REPLACE "\n" ";" listed "${listed}")
  foreach(file IN LISTS listed)
    if(NOT file STREQUAL "" AND EXISTS "${SOURCE_DIR}/${file}") # a file deleted but not yet staged has no text
      list(APPEND files "${file}")
    endif()
  endforeach()
else()
  file(GLOB files LIST_DIRECTORIES false RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/*" "${SOURCE_DIR}/.*")
  foreach(directory .ci CMake include src apps test examples benchmark wrapping docs scripts)
    file(GLOB_RECURSE found LIST_DIRECTORIES false RELATIVE "${SOURCE_DIR}" "${SOURCE_DIR}/${directory}/*")
    list(APPEND files ${found})
  endforeach()
endif()
list(REMOVE_DUPLICATES files)
list(SORT files)
list(LENGTH files count)
if(count LESS 2)
  message(FATAL_ERROR "only ${count} files found in ${SOURCE_DIR}")
endif()

# What separates the words of a citation: blanks, line breaks and the comment leaders of C++, CMake, Python and shell.
set(sep "[ \t\n/*#]")
# The outside file's name, assembled so that this script does not cite it.
set(outsideName "DESIG")
string(APPEND outsideName "N")
set(outsideCitation "${outsideName}(\\.md|${sep}+sections?${sep}+[0-9]+)")
# A section number; N.M is the paper's numbering (section 2.2.2 of the paper), not the design's.
set(number "[0-9]+(\\.[0-9]+)*")
set(numberList "${number}((${sep}*,${sep}*|${sep}+and${sep}+)${number})*")
set(projectCitations "design\\.md${sep}+section${sep}+${number}" "design\\.md${sep}+sections${sep}+${numberList}")
set(internalCitations "[Ss]ection${sep}+${number}" "[Ss]ections${sep}+${numberList}")

set(problems "")
set(citations 0)
set(binaryFiles 0)
# Appends "file:line: what: 'text'" to problems; line: where text first occurs in the variable contentVariable.
function(report file contentVariable text what)
  string(FIND "${${contentVariable}}" "${text}" position)
  string(SUBSTRING "${${contentVariable}}" 0 ${position} before)
  string(REGEX MATCHALL "\n" breaks "${before}")
  list(LENGTH breaks line)
  math(EXPR line "${line} + 1")
  string(REGEX REPLACE "${sep}+" " " shown "${text}")
  list(APPEND problems "${file}:${line}: ${what}: '${shown}'")
  set(problems "${problems}" PARENT_SCOPE)
endfunction()
# Counts the citations that match the patterns in the variable contentVariable and reports those of a section that
# docs/design.md does not have.
function(check_citations file contentVariable)
  foreach(pattern IN LISTS ARGN)
    string(REGEX MATCHALL "${pattern}" matches "${${contentVariable}}")
    foreach(match IN LISTS matches)
      string(REGEX MATCH "[0-9].*$" numbers "${match}")
      string(REGEX MATCHALL "${number}" cited "${numbers}")
      foreach(section IN LISTS cited)
        if(section MATCHES "\\.")
          continue() # the paper's numbering
        endif()
        math(EXPR citations "${citations} + 1")
        list(FIND sections "${section}" found)
        if(found EQUAL -1)
          report("${file}" ${contentVariable} "${match}" "docs/design.md has no section ${section}")
        endif()
      endforeach()
    endforeach()
  endforeach()
  set(problems "${problems}" PARENT_SCOPE)
  set(citations ${citations} PARENT_SCOPE)
endfunction()

foreach(file IN LISTS files)
  # As strings of text: a text file is one string (line breaks kept, carriage returns dropped); a binary one is cut
  # at its non-text bytes, where a regular expression would otherwise stop.
  file(STRINGS "${SOURCE_DIR}/${file}" pieces NEWLINE_CONSUME ENCODING UTF-8)
  list(LENGTH pieces numberOfPieces)
  if(numberOfPieces GREATER 1)
    math(EXPR binaryFiles "${binaryFiles} + 1")
  endif()
  list(JOIN pieces "\n" content) # the text's own semicolons stay escaped (\;), so lines count right
  string(REGEX MATCHALL "${outsideCitation}" outside "${content}")
  foreach(match IN LISTS outside)
    report("${file}" content "${match}" "cites the outside design file; cite docs/design.md section N")
  endforeach()
  check_citations("${file}" content ${projectCitations})
  if(file STREQUAL "docs/design.md")
    check_citations("${file}" content ${internalCitations})
  endif()
endforeach()

if(problems)
  list(LENGTH problems bad)
  list(JOIN problems "\n  " listing)
  message(FATAL_ERROR "${bad} design citations do not resolve (docs/design.md has sections 1 to ${numberOfSections}):"
                      "\n  ${listing}")
endif()
message(STATUS "${count} files (${binaryFiles} read as binary): ${citations} citations of docs/design.md sections, "
               "all among its sections 1 to ${numberOfSections}; no citation of the outside design file.")
