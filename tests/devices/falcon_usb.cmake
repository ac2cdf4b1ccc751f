# Falcon over libusb under umockdev: the fake FTDI answers usbdevfs ioctls inside the test process.
pkg_check_modules(UMOCKDEV IMPORTED_TARGET umockdev-1.0)
find_program(UMOCKDEV_WRAPPER umockdev-wrapper)
if(UMOCKDEV_FOUND)
  file(GLOB falcon_usb_tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/devices_usb/*_test.cpp)
  add_executable(dentsim_devices_usb_tests ${falcon_usb_tests} ${CMAKE_CURRENT_SOURCE_DIR}/devices_usb/fake_falcon.cpp)
  target_link_libraries(dentsim_devices_usb_tests PRIVATE dentsim_devices PkgConfig::UMOCKDEV
    GTest::gtest GTest::gtest_main dentsim_options dentsim_test_options)
  target_include_directories(dentsim_devices_usb_tests PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  # Without the wrapper the tests still build and each one skips, saying umockdev is missing.
  if(UMOCKDEV_WRAPPER)
    # The wrapper preloads umockdev's library. Under the sanitizers ASan insists on coming first in
    # the link order; the emulator command sets the option that lets it come second, for the test
    # discovery as much as for the runs (discovery does not see the tests' ENVIRONMENT).
    set(falcon_usb_emulator ${UMOCKDEV_WRAPPER})
    if(DENTSIM_SANITIZE)
      set(falcon_usb_emulator ${CMAKE_COMMAND} -E env
        ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:verify_asan_link_order=0 ${UMOCKDEV_WRAPPER})
    endif()
    set_target_properties(dentsim_devices_usb_tests PROPERTIES CROSSCOMPILING_EMULATOR "${falcon_usb_emulator}")
  endif()
  gtest_discover_tests(dentsim_devices_usb_tests
    DISCOVERY_MODE PRE_TEST
    DISCOVERY_TIMEOUT 60
    PROPERTIES LABELS devices TIMEOUT 120)
else()
  message(WARNING "umockdev-1.0 not found: the Falcon USB tests are not built")
endif()
