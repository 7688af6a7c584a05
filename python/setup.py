"""Builds surfkit._core against an installed libsurfkit (static, so the module needs no
libsurfkit.so at run time).

    cmake --install build --prefix P
    SURFKIT_PREFIX=P /usr/bin/python3 -m pip install --no-build-isolation python/

Without SURFKIT_PREFIX, pkg-config finds surfkit.pc on its usual path.
"""
import os
import re
import shlex
import subprocess

import numpy
from setuptools import Extension, setup

HERE = os.path.dirname(os.path.abspath(__file__))


def pkg_config(*args):
    env = dict(os.environ)
    prefix = os.environ.get("SURFKIT_PREFIX")
    if prefix:
        pc = [os.path.join(prefix, d, "pkgconfig") for d in ("lib", "lib64", "lib/x86_64-linux-gnu")]
        env["PKG_CONFIG_PATH"] = os.pathsep.join(pc + [env.get("PKG_CONFIG_PATH", "")])
    try:
        out = subprocess.run(["pkg-config", *args, "surfkit"], env=env, check=True,
                             capture_output=True, text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise SystemExit("surfkit: libsurfkit not found by pkg-config (%s); install it with "
                         "'cmake --install build --prefix P' and set SURFKIT_PREFIX=P" % e)
    return shlex.split(out)


def version():
    # the installed library's version (its core.h), else the source tree's
    return pkg_config("--modversion")[0]


cflags = pkg_config("--cflags")
WARNINGS = ["-std=c11", "-Wall", "-Wextra", "-Wshadow", "-Wstrict-prototypes",
            "-Wmissing-prototypes", "-Wformat=2", "-Wundef"]
if os.environ.get("SURFKIT_WERROR") == "1":   # python/run_tests.sh: warnings are errors
    WARNINGS.append("-Werror")
libdir = pkg_config("--variable=libdir")[0]
static_libs = [f for f in pkg_config("--static", "--libs") if f != "-lsurfkit"]

core = Extension(
    "surfkit._core",
    sources=["src/module.c", "src/calls.c"],
    include_dirs=[numpy.get_include()] + [f[2:] for f in cflags if f.startswith("-I")],
    extra_compile_args=WARNINGS + [f for f in cflags if not f.startswith("-I")],
    extra_objects=[os.path.join(libdir, "libsurfkit.a")],
    library_dirs=[f[2:] for f in static_libs if f.startswith("-L")],
    libraries=[f[2:] for f in static_libs if f.startswith("-l")],
    extra_link_args=["-Wl,--exclude-libs,ALL"] + [f for f in static_libs if not re.match("-[lL]", f)],
)

setup(version=version(), ext_modules=[core])
