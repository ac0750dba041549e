# Copies a Markdown file for installation, with the source tree's paths
# turned into the installed ones: `build/app/vssim` is `vssim` on PATH, the
# C++ example client is `vssim-example-client`, the example scenes are in
# /usr/share/vssim/scenes, the generated Python protobuf modules in
# /usr/share/vssim/python_proto.
#
#   cmake -DIN=README.md -DOUT=build/packaging/doc/README.md -P installed_doc.cmake
file(READ "${IN}" _text)
string(REPLACE "build/app/vssim" "vssim" _text "${_text}")
string(REPLACE "build/examples/cpp/vssim_example_client" "vssim-example-client" _text "${_text}")
string(REPLACE " resources/scenes/" " /usr/share/vssim/scenes/" _text "${_text}")
string(REPLACE "`resources/scenes/" "`/usr/share/vssim/scenes/" _text "${_text}")
string(REPLACE "build/python_proto" "/usr/share/vssim/python_proto" _text "${_text}")
file(WRITE "${OUT}" "${_text}")
