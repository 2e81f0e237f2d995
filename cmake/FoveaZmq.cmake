# libzmq, found once for all its users (fovead's fan-out, the daemon client, the Pupil driver) as
# fovea::zmq.
# CMake 3.25's FindPkgConfig moves libzmq's "-isystem /usr/include/mit-krb5" into the include
# directories only when it runs pkg-config, not when it reuses its cache: every re-configure then
# changed each zmq user's compile line and rebuilt it. Asking pkg-config every time (a few ms)
# keeps the second configure identical to the first.
find_package(PkgConfig REQUIRED)
unset(__pkg_config_checked_FOVEA_ZMQ CACHE)
pkg_check_modules(FOVEA_ZMQ REQUIRED IMPORTED_TARGET GLOBAL libzmq)
add_library(fovea::zmq ALIAS PkgConfig::FOVEA_ZMQ)
