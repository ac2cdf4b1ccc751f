# Script (cmake -P): writes a C++ source holding every file under ASSET_DIR/teeth, ASSET_DIR/tools,
# ASSET_DIR/presets and ASSET_DIR/tasks (the task files and their teeth) as a byte string, plus the table that src/model/embedded_assets.h declares.
# Inputs: ASSET_DIR, OUTPUT. Keep the globs equal to DENTSIM_ASSET_FILES in src/model/CMakeLists.txt.
file(GLOB_RECURSE files RELATIVE ${ASSET_DIR} ${ASSET_DIR}/teeth/*.stl ${ASSET_DIR}/tools/*.stl
  ${ASSET_DIR}/tools/*.json ${ASSET_DIR}/presets/*.json ${ASSET_DIR}/tasks/*.json ${ASSET_DIR}/tasks/*.dvol)
list(SORT files)
set(body "// Generated from assets/ by src/model/embed_assets.cmake; do not edit.\n")
string(APPEND body "#include \"model/embedded_assets.h\"\n\nnamespace dentsim::embedded {\nnamespace {\n")
set(table "")
set(n 0)
foreach(f IN LISTS files)
  file(READ ${ASSET_DIR}/${f} hex HEX)
  file(SIZE ${ASSET_DIR}/${f} size)
  # One escaped string literal per file: far quicker for the compiler than a list of integers.
  string(REGEX REPLACE "([0-9a-f][0-9a-f])" "\\\\x\\1" escaped "${hex}")
  string(APPEND body "const unsigned char kData${n}[] = \"${escaped}\";\n")
  string(APPEND table "    {\"${f}\", kData${n}, ${size}u},\n")
  math(EXPR n "${n} + 1")
endforeach()
string(APPEND body "}  // namespace\n\nconst Asset kAssets[] = {\n${table}    {nullptr, nullptr, 0u},\n};\n\n")
string(APPEND body "}  // namespace dentsim::embedded\n")
file(WRITE ${OUTPUT} "${body}")
