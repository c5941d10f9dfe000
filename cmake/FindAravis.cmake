# Aravis 0.8 (Debian libaravis-dev), found without its pkg-config file, which needs libusb's
# development package only for static linking. Defines Aravis_FOUND and Aravis::Aravis.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(ARAVIS_GLIB QUIET IMPORTED_TARGET glib-2.0 gobject-2.0 gio-2.0)
endif()
find_path(ARAVIS_INCLUDE_DIR arv.h PATH_SUFFIXES aravis-0.8)
find_library(ARAVIS_LIBRARY aravis-0.8)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Aravis REQUIRED_VARS ARAVIS_LIBRARY ARAVIS_INCLUDE_DIR ARAVIS_GLIB_FOUND)

if(Aravis_FOUND AND NOT TARGET Aravis::Aravis)
  add_library(Aravis::Aravis INTERFACE IMPORTED)
  target_include_directories(Aravis::Aravis INTERFACE ${ARAVIS_INCLUDE_DIR})
  target_link_libraries(Aravis::Aravis INTERFACE ${ARAVIS_LIBRARY} PkgConfig::ARAVIS_GLIB)
endif()
