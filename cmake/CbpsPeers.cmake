# The peers (src/solvers/peers/, docs/peers.md): Siconos numerics and Bullet's MLCP solvers as
# methods of every command (`--solver siconos:lemke`, `bullet:dantzig`, ...). Optional: with
# CBPS_PEERS (default ON: "use them when found") each library found is compiled into cbps_core
# (CBPS_HAVE_SICONOS, CBPS_HAVE_BULLET, private to it); a build without one says, when one of its
# methods is asked for, how to get it (exit 2). scripts/setup.sh installs both (Debian:
# libsiconos-numerics-dev, libbullet-dev). cbps_peers_found lists what was found, for the tests.
set(cbps_peers_found "")
if(NOT CBPS_PEERS)
  message(STATUS "cbps: peers (Siconos, Bullet) not built: CBPS_PEERS is OFF")
  return()
endif()

# Siconos numerics 4.4: its C API, header siconos/numerics/NonSmoothDrivers.h, library
# siconos_numerics. Its headers include "SiconosConfig.h" from <prefix>/include/siconos.
find_path(CBPS_SICONOS_INCLUDE_DIR siconos/numerics/NonSmoothDrivers.h)
find_library(CBPS_SICONOS_NUMERICS_LIBRARY siconos_numerics)
if(CBPS_SICONOS_INCLUDE_DIR AND CBPS_SICONOS_NUMERICS_LIBRARY)
  add_library(cbps_siconos INTERFACE IMPORTED)
  # SYSTEM: the warnings flags do not apply to Siconos' own headers.
  target_include_directories(cbps_siconos SYSTEM INTERFACE "${CBPS_SICONOS_INCLUDE_DIR}"
                             "${CBPS_SICONOS_INCLUDE_DIR}/siconos")
  target_link_libraries(cbps_siconos INTERFACE "${CBPS_SICONOS_NUMERICS_LIBRARY}")
  target_link_libraries(cbps_core PRIVATE cbps_siconos)
  target_compile_definitions(cbps_core PRIVATE CBPS_HAVE_SICONOS)
  list(APPEND cbps_peers_found siconos)
  message(STATUS "cbps: Siconos numerics found (${CBPS_SICONOS_NUMERICS_LIBRARY}): siconos:NAME")
else()
  message(STATUS "cbps: Siconos numerics not found (Debian: libsiconos-numerics-dev; "
                 "scripts/setup.sh): siconos:NAME exits 2 saying so")
endif()

# Bullet 3.24 in double precision: pkg-config's bullet-float64 (BT_USE_DOUBLE_PRECISION,
# libBulletDynamics-float64, libLinearMath-float64).
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(CBPS_BULLET QUIET IMPORTED_TARGET bullet-float64)
endif()
if(CBPS_BULLET_FOUND)
  target_link_libraries(cbps_core PRIVATE PkgConfig::CBPS_BULLET)
  target_compile_definitions(cbps_core PRIVATE CBPS_HAVE_BULLET)
  list(APPEND cbps_peers_found bullet)
  message(STATUS "cbps: Bullet ${CBPS_BULLET_VERSION} (double precision) found: bullet:NAME")
else()
  message(STATUS "cbps: Bullet in double precision not found by pkg-config (bullet-float64; "
                 "Debian: libbullet-dev; scripts/setup.sh): bullet:NAME exits 2 saying so")
endif()
