# hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
"""Run a pvpython test script as the client of a pvserver started for it.

    python3 RunClientServer.py --pvserver <pvserver> --pvpython <pvpython> \\
        [--mpiexec <mpiexec> --server-ranks N] -- <script.py> [script arguments...]

Starts pvserver with off-screen rendering on a free local port (on N ranks under mpiexec when
given, Open MPI allowed to run as root and to place more ranks than cores), runs the script with
`--server localhost:<port>` appended, and exits with the script's exit code (1 if the server
could not be started). Both processes inherit the environment (DISPLAY, PYTHONPATH).
"""
import argparse
import os
import socket
import subprocess
import sys

# Seconds: the client retries its connection for up to a minute while the server starts; a
# test that takes longer than CLIENT_TIMEOUT has hung.
CLIENT_TIMEOUT = 600
SERVER_EXIT_TIMEOUT = 30


def free_port():
    # The port is released before pvserver binds it; another process taking it in between
    # is possible but unlikely on a test machine.
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


def parse_before_script(parser, what):
    """The parser's arguments before "--", and the command after it (a script and its
    arguments), from the command line."""
    argv = sys.argv[1:]
    if "--" not in argv or argv.index("--") == len(argv) - 1:
        parser.error("no %s given after --" % what)
    split = argv.index("--")
    return parser.parse_args(argv[:split]), argv[split + 1:]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pvserver", required=True, help="the pvserver executable")
    parser.add_argument("--pvpython", required=True, help="the pvpython executable")
    parser.add_argument("--mpiexec", help="the MPI launcher, to start pvserver on several ranks")
    parser.add_argument("--server-ranks", type=int, default=1, help="pvserver's ranks")
    args, client = parse_before_script(parser, "client script")

    port = free_port()
    # Without --force-offscreen-rendering pvserver aborts on the X connection under Xvfb.
    command = [args.pvserver, "--force-offscreen-rendering", "--server-port=%d" % port]
    env = None
    if args.mpiexec and args.server_ranks > 1:
        command = [args.mpiexec, "-n", str(args.server_ranks)] + command
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_rmaps_base_oversubscribe="1")
    server = subprocess.Popen(command, env=env)
    try:
        result = subprocess.run([args.pvpython] + client + ["--server", "localhost:%d" % port],
                                timeout=CLIENT_TIMEOUT)
        code = result.returncode
    except subprocess.TimeoutExpired:
        print("the client did not finish within %d s" % CLIENT_TIMEOUT)
        code = 1
    finally:
        # pvserver exits when its client disconnects; stop it if it does not.
        try:
            server.wait(timeout=SERVER_EXIT_TIMEOUT)
        except subprocess.TimeoutExpired:
            server.terminate()
            server.wait()
    return code


if __name__ == "__main__":
    sys.exit(main())
