# The fake HDAPI library the OpenHaptics plug-in's tests load in place of libHD.so (included from tests/CMakeLists.txt).
# A MODULE: it is only ever dlopen()ed, by the plug-in and by the test that drives it.
add_library(dentsim_fake_hd MODULE ${CMAKE_CURRENT_SOURCE_DIR}/devices/fake_hd/fake_hd.cpp)
# dentsim_options brings the warnings and, in the sanitizer preset, the same sanitizers as the test.
target_link_libraries(dentsim_fake_hd PRIVATE dentsim_options Threads::Threads)
target_include_directories(dentsim_fake_hd PRIVATE ${PROJECT_SOURCE_DIR})  # devices/hdapi_abi.h
set_target_properties(dentsim_fake_hd PROPERTIES CXX_VISIBILITY_PRESET default)
if(TARGET dentsim_devices_tests)
  target_compile_definitions(dentsim_devices_tests PRIVATE DENTSIM_FAKE_HD_LIB="$<TARGET_FILE:dentsim_fake_hd>")
  target_link_libraries(dentsim_devices_tests PRIVATE ${CMAKE_DL_LIBS})
  add_dependencies(dentsim_devices_tests dentsim_fake_hd)
endif()
# The app suite runs `dentsim run --drill openhaptics:Default` under Xvfb with the fake in place of libHD.so.
if(TARGET dentsim_app_tests)
  target_compile_definitions(dentsim_app_tests PRIVATE DENTSIM_FAKE_HD_LIB="$<TARGET_FILE:dentsim_fake_hd>")
  add_dependencies(dentsim_app_tests dentsim_fake_hd)
endif()
