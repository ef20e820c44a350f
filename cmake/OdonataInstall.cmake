# What a board needs, installed (cmake --install) or packaged (cpack -G DEB): the programs, the
# orchestration scripts, the lcm-spy launcher and types jar, systemd units with example
# settings, the flight-code inference header and the examples. README "Install on a board".
include(GNUInstallDirs)

install(TARGETS odonata-plant odonata-signal odonata-identifier odonata-monitor odonata-logger
                odonata-control odonata-fit odonata-sim odonata-export
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Scripts find the programs beside themselves when installed (their own folder is bin/).
install(PROGRAMS deploy/odonata-run DESTINATION ${CMAKE_INSTALL_BINDIR})
install(PROGRAMS deploy/make-identifier-config DESTINATION ${CMAKE_INSTALL_BINDIR}
        RENAME odonata-make-identifier-config)
install(PROGRAMS deploy/lcm-spy.sh DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME odonata-lcm-spy)
# The one rule both scripts use to find the programs (imported from the scripts' own folder).
install(FILES deploy/odonata_programs.py DESTINATION ${CMAKE_INSTALL_BINDIR})
install(PROGRAMS deploy/odonata-compare DESTINATION ${CMAKE_INSTALL_BINDIR})
# bash-completion loads a command's completion from a file of its name.
foreach(_p odonata-plant odonata-signal odonata-identifier odonata-monitor odonata-logger
        odonata-control odonata-fit odonata-sim odonata-export odonata-run odonata-compare
        odonata-make-identifier-config)
  install(FILES deploy/odonata.bash-completion
          DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions RENAME ${_p})
endforeach()
install(FILES deploy/odonata_compare.py DESTINATION ${CMAKE_INSTALL_BINDIR})
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
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY deploy/board/ DESTINATION ${CMAKE_INSTALL_DATADIR}/odonata/board
        PATTERN "*.service" EXCLUDE PATTERN "*.target" EXCLUDE)
# Units name /usr/bin and /etc/odonata; a staging prefix keeps them as reference copies.
install(DIRECTORY deploy/board/ DESTINATION lib/systemd/system
        FILES_MATCHING PATTERN "*.service" PATTERN "*.target")

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME odonata)
set(CPACK_PACKAGE_VENDOR "odonata")
set(CPACK_PACKAGE_CONTACT "odonata developers <odonata@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Online entropy-fuzzy identification of flapping-wing vehicles over LCM")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# liblcm1 for the programs, python3 for odonata-run; the Java side only for lcm-spy.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "liblcm1, python3")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-bin, liblcm-java, libjchart2d-java, default-jre")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
include(CPack)
