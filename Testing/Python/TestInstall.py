"""``cmake --install`` gives a usable package: ``import hovr`` works from the install tree (in
a fresh process, without the build tree on any path) and a downstream CMake project builds
against it with find_package(hovr) and runs."""

import os
import shutil
import subprocess
import sys
import tempfile

from hovrtesting import Checker, ROOT

c = Checker()
build = os.environ["HOVR_BUILD"]
tmp = tempfile.mkdtemp(prefix="hovr-install-")
prefix = os.path.join(tmp, "prefix")


def run(command, **kwargs):
    process = subprocess.run(command, capture_output=True, text=True, **kwargs)
    if process.returncode != 0:
        print("$ " + " ".join(command))
        print(process.stdout[-3000:])
        print(process.stderr[-3000:])
    return process


c.check(run(["cmake", "--install", build, "--prefix", prefix]).returncode == 0,
        "cmake --install succeeds")
packages = [os.path.join(root, name) for root, dirs, _ in os.walk(prefix) for name in dirs
            if name == "hovr" and os.path.isfile(os.path.join(root, name, "__init__.py"))]
c.check(len(packages) == 1, "one installed hovr package (%s)" % packages)
env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "HOVR_BUILD")}
if packages:
    env["PYTHONPATH"] = os.path.dirname(packages[0])
    probe = run([sys.executable, "-c", "import hovr, sys; "
                 "m = hovr.vtkPreIntegrationVolumeMapper(); "
                 "assert '%s' not in hovr.__file__; print(hovr.__file__)" % build], env=env,
                cwd=tmp)
    c.check(probe.returncode == 0, "import hovr from the install tree")
    c.check(probe.stdout.startswith(prefix), "the installed package is the one imported (%s)"
            % probe.stdout.strip())

config_dirs = [root for root, _, files in os.walk(prefix) if "hovr-config.cmake" in files]
c.check(len(config_dirs) == 1, "hovr-config.cmake installed")
if config_dirs:
    example_build = os.path.join(tmp, "example")
    configure = run(["cmake", "-S", os.path.join(ROOT, "Examples", "Cxx"), "-B", example_build,
                     "-Dhovr_DIR=" + config_dirs[0], "-DCMAKE_BUILD_TYPE=Release"], env=env)
    c.check(configure.returncode == 0, "a downstream project configures with find_package(hovr)")
    compile_ = run(["cmake", "--build", example_build, "-j", "2"], env=env)
    c.check(compile_.returncode == 0, "the downstream project builds")
    binary = os.path.join(example_build, "PreIntegratedVolume")
    if os.path.isfile(binary):
        result = run([binary, os.path.join(tmp, "downstream.png")], env=env)
        c.check(result.returncode == 0, "the downstream program runs against the installed "
                "libraries: " + result.stdout.strip())
        libs = run(["ldd", binary], env=env).stdout
        c.check(build not in libs, "the downstream program does not load the build tree")
shutil.rmtree(tmp, ignore_errors=True)
c.finish()
