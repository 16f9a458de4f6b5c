# Finds OpenVDB (target OpenVDB::openvdb) for ifsforge's build and for ifsforgeConfig.cmake.
# OpenVDB installs a find-module (FindOpenVDB.cmake, with its helpers) rather than a package
# config, in <prefix>/lib/cmake/OpenVDB, or lib/<multiarch>/cmake/OpenVDB on Debian. That folder
# is looked for below the prefixes find_package searches (OpenVDB_ROOT, CMAKE_PREFIX_PATH, the
# system's), and joins CMAKE_MODULE_PATH for the one call: FindOpenVDB finds its own
# dependencies (TBB, Blosc) through it. Set IFSFORGE_OPENVDB_MODULE_DIR to choose the folder.
# Where no find-module is found, find_package falls back to an OpenVDBConfig.cmake.
#
# ifsforge_find_openvdb([REQUIRED] [QUIET]) sets OpenVDB_FOUND in the caller's scope.
macro(ifsforge_find_openvdb)
  if(NOT IFSFORGE_OPENVDB_MODULE_DIR)
    set(_ifsforge_prefixes ${OpenVDB_ROOT} $ENV{OpenVDB_ROOT} ${CMAKE_PREFIX_PATH})
    if(DEFINED ENV{CMAKE_PREFIX_PATH})
      file(TO_CMAKE_PATH "$ENV{CMAKE_PREFIX_PATH}" _ifsforge_env_prefixes)
      list(APPEND _ifsforge_prefixes ${_ifsforge_env_prefixes})
    endif()
    list(APPEND _ifsforge_prefixes ${CMAKE_SYSTEM_PREFIX_PATH})
    set(_ifsforge_suffixes lib/cmake/OpenVDB lib64/cmake/OpenVDB share/OpenVDB/cmake)
    if(CMAKE_LIBRARY_ARCHITECTURE)
      list(PREPEND _ifsforge_suffixes lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB)
    endif()
    find_path(IFSFORGE_OPENVDB_MODULE_DIR FindOpenVDB.cmake
      PATHS ${_ifsforge_prefixes} PATH_SUFFIXES ${_ifsforge_suffixes} NO_DEFAULT_PATH
      DOC "Folder of OpenVDB's FindOpenVDB.cmake")
    unset(_ifsforge_prefixes)
    unset(_ifsforge_env_prefixes)
    unset(_ifsforge_suffixes)
  endif()
  set(_ifsforge_saved_module_path "${CMAKE_MODULE_PATH}")
  if(IFSFORGE_OPENVDB_MODULE_DIR)
    list(PREPEND CMAKE_MODULE_PATH "${IFSFORGE_OPENVDB_MODULE_DIR}")
  endif()
  find_package(OpenVDB ${ARGN})
  set(CMAKE_MODULE_PATH "${_ifsforge_saved_module_path}")
  unset(_ifsforge_saved_module_path)
endmacro()
