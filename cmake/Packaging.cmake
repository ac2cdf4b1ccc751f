# Packaging: what `cmake --install` puts where, and the Debian package `cpack -G DEB` makes of it for lab PCs that do not build from source.
#
# Layout under the prefix (/usr in the package):
#   bin/dentsim                          the program (stripped by cpack); assets and SPIR-V are embedded in it
#   share/dentsim/{teeth,tools,presets}  the built-in molar, neighbours, tools and preset as files a teacher copies
#   share/dentsim/tasks                  the default course: `run` lists it outside a source tree (app/data_folder.h)
#   share/man/man1/dentsim.1.gz          the man page, written from the program's own --help (cmake/man-page.sh)
#   lib/udev/rules.d/70-dentsim.rules    pens, pedals and the idle-latency request for the user at the seat
# No test, fake driver or benchmark peer is installed: only these rules exist.
include(GNUInstallDirs)

set(DENTSIM_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/dentsim)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)  # the package's prefix, whatever CMAKE_INSTALL_PREFIX is

# The binary finds share/dentsim relative to itself, so an unpacked or relocated tree works as well as
# /usr. The relative path comes from the same two directories the rules below install into.
file(RELATIVE_PATH dentsim_data_from_bindir /prefix/${CMAKE_INSTALL_BINDIR} /prefix/${DENTSIM_INSTALL_DATADIR})
set_source_files_properties(${PROJECT_SOURCE_DIR}/src/app/data_folder.cpp DIRECTORY ${PROJECT_SOURCE_DIR}/src/app
  PROPERTIES COMPILE_DEFINITIONS "DENTSIM_DATA_FROM_BINDIR=\"${dentsim_data_from_bindir}\"")

install(TARGETS dentsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets/teeth ${PROJECT_SOURCE_DIR}/assets/tools ${PROJECT_SOURCE_DIR}/assets/presets
                  ${PROJECT_SOURCE_DIR}/assets/tasks
  DESTINATION ${DENTSIM_INSTALL_DATADIR})
install(FILES ${PROJECT_SOURCE_DIR}/assets/README.md ${PROJECT_SOURCE_DIR}/assets/LICENSE-MIT-rl-baselines3-zoo-dental.txt
  DESTINATION ${DENTSIM_INSTALL_DATADIR})
# udev reads /usr/lib/udev/rules.d (a package's place; /etc/udev/rules.d is the admin's) and picks a
# new rule up on the next device event: replug the pen. Not CMAKE_INSTALL_LIBDIR, which is multiarch.
install(FILES ${PROJECT_SOURCE_DIR}/devices/70-dentsim.rules DESTINATION lib/udev/rules.d)

# ---- the man page: every command's --help, run from the built binary -------------------------------
find_program(GZIP gzip REQUIRED)
set(dentsim_man ${PROJECT_BINARY_DIR}/man/dentsim.1)
add_custom_command(
  OUTPUT ${dentsim_man}.gz
  COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
  # Leak checks off: a sanitizer build runs the binary here only to read its help.
  COMMAND ${CMAKE_COMMAND} -E env ASAN_OPTIONS=detect_leaks=0
          sh ${PROJECT_SOURCE_DIR}/cmake/man-page.sh $<TARGET_FILE:dentsim> ${PROJECT_VERSION}
          ${CPACK_PACKAGING_INSTALL_PREFIX}/${DENTSIM_INSTALL_DATADIR}
          ${dentsim_man}
  # -n: no name or time in the gzip header, so the page is the same bytes every build.
  COMMAND ${GZIP} -9nf ${dentsim_man}
  DEPENDS dentsim ${PROJECT_SOURCE_DIR}/cmake/man-page.sh
  COMMENT "man page dentsim.1 from dentsim --help"
  VERBATIM)
add_custom_target(dentsim_man ALL DEPENDS ${dentsim_man}.gz)
install(FILES ${dentsim_man}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)

# ---- the Debian package --------------------------------------------------------------------------
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME dentsim)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "dentsim team")
set(CPACK_PACKAGE_CONTACT "dentsim team <team@dentsim.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "dental surgery simulator for teaching: drill a voxel tooth, feel it, get a score")
# One paragraph in lines under 80 characters, as dpkg shows it.
string(JOIN "\n" CPACK_PACKAGE_DESCRIPTION
  "A student drills a tooth from CT or STL with a haptic pen (Novint Falcon,"
  "3D Systems Touch) or the mouse, sees it through a dental mirror, hears the"
  "turbine, and is scored against a professional's cut. Teachers write tasks"
  "and courses, record ideals and read class reports; scored attempts go to"
  "the school's LRS as xAPI statements. Needs a Vulkan 1.2 device: any GPU, or"
  "Mesa's lavapipe on the CPU.")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # dentsim_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CPACK_PACKAGE_CONTACT}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The shared libraries dentsim links (Vulkan's loader, GLFW, OpenAL, libusb, hidapi, curl, GDCM, ...)
# become Depends through dpkg-shlibdeps (dpkg-dev). The loader needs a driver, which nothing links:
# Mesa's drivers or any package that provides vulkan-icd. A build with DENTSIM_BUILD_BENCH links the benchmark
# peers, so its package depends on VTK and OpenVDB too (README: a lab's build turns them off).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "mesa-vulkan-drivers | vulkan-icd")
include(CPack)
