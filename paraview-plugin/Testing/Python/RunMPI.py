# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""Run a pvbatch test script on one rank, then on several under MPI, each MPI run comparing
its images with the first's.

    python3 RunMPI.py --mpiexec <mpiexec> --pvbatch <pvbatch> --ranks 2 [3 ...] \\
        --output-dir <dir> -- <script.py> [script arguments...]

The one-rank run gets `--output-dir <dir>/1`; the MPI run on N ranks gets `--output-dir
<dir>/<N> --compare-dir <dir>/1 --ranks <N>`, for each N given. Exits with the first failing
run's exit code. Both
runs inherit the environment (DISPLAY, PYTHONPATH); Open MPI is allowed to run as root and
to place more ranks than cores (a CI container), through its environment variables, which
other MPI implementations ignore. Under Xvfb, start it with -noreset: the MPI run connects
right after the one-rank run leaves, when a resetting server refuses connections.
"""
import argparse
import os
import subprocess
import sys

from RunClientServer import parse_before_script  # (this script's directory)

# Seconds after which a run has hung.
RUN_TIMEOUT = 600


def run(command, env):
    print(" ".join(command), flush=True)
    try:
        return subprocess.run(command, env=env, timeout=RUN_TIMEOUT).returncode
    except subprocess.TimeoutExpired:
        print("did not finish within %d s" % RUN_TIMEOUT)
        return 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mpiexec", required=True, help="the MPI launcher")
    parser.add_argument("--pvbatch", required=True, help="the pvbatch executable")
    parser.add_argument("--ranks", type=int, nargs="+", default=[2],
                        help="processes of the MPI runs, one run each")
    parser.add_argument("--output-dir", required=True, help="where both runs write images")
    args, script = parse_before_script(parser, "test script")

    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    single = os.path.join(args.output_dir, "1")
    code = run([args.pvbatch] + script + ["--output-dir", single], env)
    if code != 0:
        return code
    for ranks in args.ranks:
        code = run([args.mpiexec, "-n", str(ranks), args.pvbatch] + script +
                   ["--output-dir", os.path.join(args.output_dir, str(ranks)),
                    "--compare-dir", single, "--ranks", str(ranks)], env)
        if code != 0:
            return code
    return 0


if __name__ == "__main__":
    sys.exit(main())
