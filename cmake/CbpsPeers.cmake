# The peers (src/solvers/peers/, docs/peers.md): Siconos numerics and Bullet's MLCP solvers as
# methods of every command (`--solver siconos:lemke`, `bullet:dantzig`, ...). Optional: with
# CBPS_PEERS (default ON: "use them when found") each library found is compiled into cbps_core
# (CBPS_HAVE_SICONOS, CBPS_HAVE_BULLET, private to it); a build without one says, when one of its
# methods is asked for, how to get it (exit 2). scripts/setup.sh installs both (Debian:
# libsiconos-numerics-dev, libbullet-dev). cbps_peers_found lists what was found, for the tests.
set(cbps_peers_found "")
set(cbps_peers_missing "")
set(cbps_peers_why "not found")
if(NOT CBPS_PEERS)
  set(cbps_peers_why "not built (CBPS_PEERS is OFF)")
endif()

# Siconos numerics 4.4: its C API, header siconos/numerics/NonSmoothDrivers.h, library
# siconos_numerics. Its headers include "SiconosConfig.h" from <prefix>/include/siconos.
if(CBPS_PEERS)
  find_path(CBPS_SICONOS_INCLUDE_DIR siconos/numerics/NonSmoothDrivers.h)
  find_library(CBPS_SICONOS_NUMERICS_LIBRARY siconos_numerics)
endif()
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
  message(STATUS "cbps: Siconos numerics ${cbps_peers_why} (Debian: libsiconos-numerics-dev; "
                 "scripts/setup.sh): siconos:NAME exits 2 saying so")
  list(APPEND cbps_peers_missing "siconos:lemke;libsiconos-numerics-dev")
endif()

# Bullet 3.24 in double precision: pkg-config's bullet-float64 (BT_USE_DOUBLE_PRECISION,
# libBulletDynamics-float64, libLinearMath-float64).
find_package(PkgConfig QUIET)
if(CBPS_PEERS AND PkgConfig_FOUND)
  pkg_check_modules(CBPS_BULLET QUIET IMPORTED_TARGET bullet-float64)
endif()
if(CBPS_BULLET_FOUND)
  target_link_libraries(cbps_core PRIVATE PkgConfig::CBPS_BULLET)
  if(CBPS_SANITIZE)
    # Bullet's MLCP solvers are inline in its headers, so they are compiled in bullet.cpp: their
    # arithmetic is Bullet's, not cbps's (btLemkeSolver's Gauss-Jordan divides by a zero pivot of
    # a singular A by design, which -fsanitize=float-divide-by-zero would stop). UBSan stays off
    # for that one file; AddressSanitizer stays on.
    set_source_files_properties("${PROJECT_SOURCE_DIR}/src/solvers/peers/bullet.cpp" PROPERTIES
                                COMPILE_OPTIONS "-fno-sanitize=undefined,float-divide-by-zero")
  endif()
  target_compile_definitions(cbps_core PRIVATE CBPS_HAVE_BULLET)
  list(APPEND cbps_peers_found bullet)
  message(STATUS "cbps: Bullet ${CBPS_BULLET_VERSION} (double precision) found: bullet:NAME")
else()
  message(STATUS "cbps: Bullet in double precision ${cbps_peers_why} (pkg-config bullet-float64; "
                 "Debian: libbullet-dev; scripts/setup.sh): bullet:NAME exits 2 saying so")
  list(APPEND cbps_peers_missing "bullet:dantzig;libbullet-dev")
endif()

# What a build without a peer does instead: asking for it exits 2 naming the package.
if(CBPS_BUILD_TESTS AND cbps_peers_missing)
  while(cbps_peers_missing)
    list(POP_FRONT cbps_peers_missing _peer _package)
    string(REGEX REPLACE ":.*" "" _library "${_peer}")
    add_test(NAME peers-${_library}-not-built-exits-2
             COMMAND "${CBPS_PLOT_PYTHON}" "${PROJECT_SOURCE_DIR}/tests/test_peer_not_built.py"
                     "${PROJECT_SOURCE_DIR}" $<TARGET_FILE:cbps> "${_peer}" "${_package}")
    set_tests_properties(peers-${_library}-not-built-exits-2 PROPERTIES LABELS peers TIMEOUT 60)
  endwhile()
endif()

# MuJoCo 2.2 (Debian: libmujoco-dev): `cbps mujoco` exports the constraint problem of a step
# of MuJoCo's own as a cbps problem (src/io/mujoco_problem.cpp, docs/mujoco.md). Optional like the
# peers: without it, `cbps mujoco` exits 2 saying how to get it.
# Found by its header and library: Debian's mujocoConfig.cmake names qhull's headers, which
# libmujoco-dev does not bring.
if(CBPS_PEERS)
  find_path(CBPS_MUJOCO_INCLUDE_DIR mujoco/mujoco.h)
  find_library(CBPS_MUJOCO_LIBRARY mujoco)
endif()
if(CBPS_MUJOCO_INCLUDE_DIR AND CBPS_MUJOCO_LIBRARY)
  add_library(cbps_mujoco INTERFACE IMPORTED)
  target_include_directories(cbps_mujoco SYSTEM INTERFACE "${CBPS_MUJOCO_INCLUDE_DIR}")
  target_link_libraries(cbps_mujoco INTERFACE "${CBPS_MUJOCO_LIBRARY}")
  target_link_libraries(cbps_core PRIVATE cbps_mujoco)
  target_compile_definitions(cbps_core PRIVATE CBPS_HAVE_MUJOCO)
  list(APPEND cbps_peers_found mujoco)
  message(STATUS "cbps: MuJoCo found (${CBPS_MUJOCO_LIBRARY}): cbps mujoco")
else()
  message(STATUS "cbps: MuJoCo ${cbps_peers_why} (Debian: libmujoco-dev; scripts/setup.sh): "
                 "cbps mujoco exits 2 saying so")
endif()
