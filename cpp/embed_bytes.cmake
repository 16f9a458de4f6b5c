# cmake -DINPUT=file -DOUTPUT=header.h -P embed_bytes.cmake: writes the bytes of INPUT as
# `constexpr unsigned char kIfsforgeInc[]` (no terminator: the array holds the file exactly).
file(READ ${INPUT} hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
string(REGEX REPLACE "((0x..,){20})" "\\1\n  " bytes "${bytes}")
file(WRITE ${OUTPUT}.tmp "// Generated from ${INPUT} by cpp/embed_bytes.cmake: do not edit.\n#pragma once\n\nnamespace ifsforge {\n\nconstexpr unsigned char kIfsforgeInc[] = {\n  ${bytes}\n};\n\n}  // namespace ifsforge\n")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
