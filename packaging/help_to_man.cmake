# Writes a man page (section 1, gzipped as Debian wants) from a command's
# --help text, so the pages never disagree with the program.
#
#   cmake -DVSSIM=path/to/vssim -DCOMMAND=run -DSUMMARY="..." -DVERSION=0.1.0
#         -DOUT=vssim-run.1.gz -P help_to_man.cmake
#
# COMMAND empty: the page of `vssim` itself. The help text goes in verbatim
# (no-fill), with its "Usage: ..." line as the synopsis.
foreach(_var VSSIM SUMMARY VERSION OUT)
    if(NOT DEFINED ${_var})
        message(FATAL_ERROR "help_to_man.cmake: -D${_var}=... is required")
    endif()
endforeach()

if(COMMAND)
    set(_name "vssim-${COMMAND}")
    set(_args ${COMMAND} --help)
else()
    set(_name "vssim")
    set(_args --help)
endif()
# Without a display, so that `vssim gui --help` needs none either.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=DISPLAY --unset=WAYLAND_DISPLAY QT_QPA_PLATFORM=offscreen
                        ${VSSIM} ${_args}
                OUTPUT_VARIABLE _help ERROR_VARIABLE _err RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0 OR _help STREQUAL "")
    message(FATAL_ERROR "help_to_man.cmake: '${VSSIM} ${_args}' failed (exit ${_rc}): ${_err}")
endif()

# roff: a backslash is \e, a hyphen-minus \-, and a line may not start with . or '.
string(REPLACE "\\" "\\e" _help "${_help}")
string(REPLACE "-" "\\-" _help "${_help}")
string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" _help "${_help}")

if(COMMAND)
    set(_synopsis "vssim ${COMMAND} [options]")
else()
    set(_synopsis "vssim [COMMAND] [options]")
endif()
if(_help MATCHES "(^|\n)Usage: ([^\n]+)\n")
    set(_synopsis "${CMAKE_MATCH_2}")
    string(REGEX REPLACE "(^|\n)Usage: [^\n]+\n" "\\1" _help "${_help}")
endif()
string(REGEX REPLACE "^\n+" "" _help "${_help}")
string(TOUPPER "${_name}" _title)
string(REPLACE "-" "\\-" _escapedName "${_name}")
string(REPLACE "-" "\\-" _summary "${SUMMARY}")

set(_page ".TH ${_title} 1 \"\" \"vssim ${VERSION}\" \"User Commands\"
.SH NAME
${_escapedName} \\- ${_summary}
.SH SYNOPSIS
.nf
${_synopsis}
.fi
.SH DESCRIPTION
.nf
${_help}.fi
.SH FILES
.TP
/usr/share/vssim/scenes
the example scenes, also usable by name (kickoff_3v3, robot_hits_ball, ...)
.TP
/usr/share/doc/vssim
the documentation: docs/scenes.md (scene files), docs/protocol.md (the TCP protocol),
docs/app.md (the desktop app), docs/model.md (the physical model)
.SH SEE ALSO
vssim(1), vssim\\-gui(1), vssim\\-run(1), vssim\\-serve(1), vssim\\-match(1), vssim\\-stress(1), vssim\\-demo(1)
")
get_filename_component(_dir "${OUT}" DIRECTORY)
file(MAKE_DIRECTORY "${_dir}")
string(REGEX REPLACE "\\.gz$" "" _plain "${OUT}")
file(WRITE "${_plain}" "${_page}")
# -n: no name or time stamp in the archive, so builds are reproducible.
execute_process(COMMAND gzip -9nf "${_plain}" RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "help_to_man.cmake: gzip -9n ${_plain} failed")
endif()
