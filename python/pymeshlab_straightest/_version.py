# Replaced by scripts/make-wheel.sh with the project version from CMakeLists.txt.
VERSION = "0.0.0"
