# What a board needs, installed (cmake --install) or packaged (cpack -G DEB): the programs, the
# orchestration scripts, the lcm-spy launcher and types jar, systemd units with example
# settings, the flight-code inference header and the examples. docs/guide/install-on-a-board.md.
include(GNUInstallDirs)

set(_odonata_installed odonata-plant odonata-signal odonata-identifier odonata-monitor
    odonata-logger odonata-control odonata-fit odonata-sim odonata-export odonata-replay odonata-ulog odonata-log
    odonata-mavlink)
# A package for any x86-64 that still fits 1.5x faster where AVX2 and FMA exist (docs/reference/benchmarks.md,
# the x86-64 levels): deploy/package.sh builds this tree for baseline x86-64 and a second one for
# x86-64-v3 (ODONATA_V3_TREE); both sets of programs go to libexec/odonata/<level>/, and bin/
# holds a launcher per program that runs the level glibc's loader says this CPU supports.
set(ODONATA_V3_TREE "" CACHE PATH
    "build tree of this source for x86-64-v3 whose programs to package beside this tree's")
file(RELATIVE_PATH _odonata_levels_from_bin /p/${CMAKE_INSTALL_BINDIR}
     /p/${CMAKE_INSTALL_LIBEXECDIR}/odonata)
set(ODONATA_LEVELS_FROM_BIN ${_odonata_levels_from_bin})
configure_file(${PROJECT_SOURCE_DIR}/deploy/odonata-arch-launcher.in
               ${PROJECT_BINARY_DIR}/odonata-arch-launcher @ONLY)
if(ODONATA_V3_TREE)
  if(ODONATA_X86_64_V3)
    message(FATAL_ERROR "ODONATA_V3_TREE needs this tree built for baseline x86-64 "
                        "(-DODONATA_NATIVE_ARCH=OFF)")
  endif()
  install(TARGETS ${_odonata_installed}
          RUNTIME DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/odonata/x86-64)
  foreach(_p IN LISTS _odonata_installed)
    string(REPLACE "odonata-" "" _dir ${_p})
    install(PROGRAMS ${ODONATA_V3_TREE}/services/${_dir}/${_p}
            DESTINATION ${CMAKE_INSTALL_LIBEXECDIR}/odonata/x86-64-v3)
    install(PROGRAMS ${PROJECT_BINARY_DIR}/odonata-arch-launcher
            DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME ${_p})
  endforeach()
else()
  install(TARGETS ${_odonata_installed} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
# Scripts find the programs beside themselves when installed (their own folder is bin/).
install(PROGRAMS deploy/odonata-run DESTINATION ${CMAKE_INSTALL_BINDIR})
install(PROGRAMS deploy/make-identifier-config DESTINATION ${CMAKE_INSTALL_BINDIR}
        RENAME odonata-make-identifier-config)
install(PROGRAMS deploy/lcm-spy.sh DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME odonata-lcm-spy)
# The one rule both scripts use to find the programs (imported from the scripts' own folder).
# The scripts' helper modules: not programs, so not in bin/.
install(PROGRAMS deploy/fit_plots.py deploy/fit_report.py DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/python)
install(FILES deploy/odonata_programs.py deploy/odonata_compare.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/python)
# fit_report.py's page and verdict (odonata-fit --report) are in the report's package.
install(DIRECTORY deploy/odonata_report DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/python
        FILES_MATCHING PATTERN "*.py")
install(PROGRAMS deploy/odonata-compare DESTINATION ${CMAKE_INSTALL_BINDIR})
# bash-completion loads a command's completion from a file of its name.
foreach(_p odonata-plant odonata-signal odonata-identifier odonata-monitor odonata-logger
        odonata-control odonata-fit odonata-sim odonata-export odonata-replay odonata-ulog odonata-log odonata-mavlink odonata-run odonata-compare
        odonata-make-identifier-config)
  install(FILES deploy/odonata.bash-completion
          DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME ${_p})
endforeach()
if(ODONATA_TYPES_JAR)
  install(FILES ${ODONATA_TYPES_JAR} DESTINATION ${CMAKE_INSTALL_DATADIR}/java)
endif()
install(DIRECTORY lcmtypes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/lcmtypes
        FILES_MATCHING PATTERN "*.lcm")
install(FILES common/inference/odonata/tsk_model.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/odonata)
install(DIRECTORY examples/ DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/examples)
# A vehicle in Python publishes signals_t with this module (standard library only).
install(FILES python/odonata_signals.py DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/python)
# Under docs/, as in the source tree, so the installed README.md's links resolve.
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)
install(FILES README.md deploy/copyright DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY deploy/board/ DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/board
        PATTERN "*.service" EXCLUDE PATTERN "*.target" EXCLUDE)
# The units start the programs where this installation puts them (the prefix is known only at
# install time: `cmake --install --prefix`, or cpack's /usr), with settings in /etc/odonata.
file(GLOB _units ${PROJECT_SOURCE_DIR}/deploy/board/*.service ${PROJECT_SOURCE_DIR}/deploy/board/*.target)
foreach(_unit IN LISTS _units)
  get_filename_component(_name ${_unit} NAME)
  install(CODE "
    file(READ \"${_unit}\" _text)
    string(REPLACE \"/usr/bin/\" \"\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/\" _text \"\${_text}\")
    string(REPLACE \"file:/usr/share/doc/odonata/\" \"file:\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_DOCDIR}/\" _text \"\${_text}\")
    file(WRITE \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/systemd/system/${_name}\" \"\${_text}\")
    message(STATUS \"Installing: \$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/lib/systemd/system/${_name}\")")
endforeach()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME odonata)
set(CPACK_PACKAGE_VENDOR "odonata")
set(CPACK_PACKAGE_CONTACT "odonata developers <odonata@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Online entropy-fuzzy identification of flapping-wing vehicles over LCM")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# python3 for the scripts, iproute2 for odonata-run's private network namespace (unshare is in
# util-linux, which every Debian has); liblcm1 and the C++ runtime come from dpkg-shlibdeps
# (once); the Java side only for lcm-spy. tests/install/fresh_root_test.sh installs the package
# into a bare bookworm root, so a missing dependency fails there.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3, iproute2")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-bin, liblcm-java, libjchart2d-java, default-jre")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
if(ODONATA_V3_TREE)
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
      "${CPACK_PACKAGE_DESCRIPTION_SUMMARY} (AVX2 builds chosen at run time)")
elseif(ODONATA_X86_64_V3)
  # Built for this machine's AVX2 and FMA: a board without them would stop at an illegal
  # instruction, so the version and the description say so. deploy/package.sh builds the
  # package for any x86-64.
  set(CPACK_DEBIAN_PACKAGE_VERSION "${PROJECT_VERSION}+x86-64-v3")
  set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
      "${CPACK_PACKAGE_DESCRIPTION_SUMMARY} (needs AVX2 and FMA: x86-64-v3)")
endif()
include(CPack)
