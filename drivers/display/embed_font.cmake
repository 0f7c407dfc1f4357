# Build step: a gzip'd PSF2 console font -> a C array (the board has no
# /usr/share/consolefonts; the font travels inside the binary and is parsed
# at start by pv_font_parse_psf2). Usage:
#   cmake -DIN=font.psf.gz -DOUT=font.c -DNAME=pv_font_x -P embed_font.cmake
get_filename_component(out_dir ${OUT} DIRECTORY)
set(psf ${out_dir}/${NAME}.psf)
execute_process(COMMAND gzip -dc ${IN} OUTPUT_FILE ${psf} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cannot gunzip ${IN}")
endif()
file(READ ${psf} hex HEX)
string(LENGTH "${hex}" n)
math(EXPR bytes "${n} / 2")
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," body "${hex}")
string(REGEX REPLACE "((0x..,){16})" "\\1\n  " body "${body}")
file(WRITE ${OUT}
  "/* Generated from ${NAME} (Terminus Font, SIL OFL 1.1) by embed_font.cmake. */\n"
  "#include <stddef.h>\n#include <stdint.h>\n"
  "const uint8_t ${NAME}[${bytes}] = {\n  ${body}\n};\n"
  "const size_t ${NAME}_bytes = ${bytes};\n")
