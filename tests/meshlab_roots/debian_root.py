"""How the tests run a program inside a Debian root of scripts/make-meshlab-root.sh.

One mechanism for the GUI test, the headless harness and the package test: chroot in a private
mount namespace, where the root gets /proc (and, for a GUI, the host's X socket) for that process
tree only, so nothing stays mounted when it ends and the host is not touched. No PID namespace:
the program would be its PID 1, which ignores SIGTERM. The environment is emptied but for PATH
and what the caller passes. chroot starts the program in the root's /.
"""

PATH = "/usr/sbin:/usr/bin:/sbin:/bin"


def command(root, argv, env=None, x11=False):
    """The host command line that runs argv (paths inside the root) in the root."""
    mounts = 'mount -t proc proc "$0/proc"'
    if x11:
        mounts += ' && mkdir -p "$0/tmp/.X11-unix" && mount --bind /tmp/.X11-unix "$0/tmp/.X11-unix"'
    variables = ["PATH=" + PATH] + ["%s=%s" % item for item in (env or {}).items()]
    return (["unshare", "--mount", "--propagation", "private", "sh", "-c",
             mounts + ' && exec chroot "$0" env -i "$@"', root] + variables + list(argv))
