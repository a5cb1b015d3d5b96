"""What every part of the core shares: the limits, names and exceptions (docs/architecture.md,
"The shared core")."""
import datetime, os, signal, sys

MAX_INPUT_BYTES = 4 << 30           # clouds, traces
MAX_SETTINGS_BYTES = 64 << 20       # JSON, CSV and text settings
MAX_JSON_DEPTH = 512
MANIFEST = "manifest.json"
TMP_PREFIX = ".tigris-tmp-"
PARENT_ENV = "TIGRIS_PARENT_OUTPUTS"
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
KILL_AFTER = 5.0                    # SIGTERM to a child's group, then SIGKILL after this long
SBATCH_FAILED = 3                   # the exit code of a failed Slurm submission, in every command
COMMIT_ENV = "TIGRIS_COMMIT"        # the tigris binary sets it for every Python tool it runs


class Refused(Exception):
    """A bad argument, input or output folder: the command prints it and exits 2."""


class SlurmFailed(Exception):
    """sbatch missing or refusing: the command prints it and exits 3."""


class Interrupted(KeyboardInterrupt):
    """SIGINT, SIGTERM or SIGHUP to the parent: exit 128 + signum after stopping every child."""
    def __init__(self, signum=signal.SIGINT):
        super().__init__(signum)
        self.signum = signum


def now_utc():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def size_text(b):
    return f"{b >> 30} GiB" if b >= 1 << 30 else f"{b >> 20} MiB" if b >= 1 << 20 else f"{b} bytes"


def dotted(obj, prefix=""):
    """A nested JSON object as {dotted key: leaf}, in order: {"fe": {"recursion_units": 16}} as
    {"fe.recursion_units": 16}. Comment members ("//...") are left out; an empty object and a list
    are leaves (the top-level empty object gives {}). The one flattener of configurations,
    presets, settings and stats."""
    if isinstance(obj, dict) and (obj or not prefix):
        out = {}
        for k, v in obj.items():
            if isinstance(k, str) and k.startswith("//"):
                continue
            out.update(dotted(v, f"{prefix}.{k}" if prefix else str(k)))
        return out
    return {prefix: obj}


def tigris_commit():
    """The tigris commit that runs this tool ($TIGRIS_COMMIT, as the binary's build_commit(): a
    hash, "-dirty" when the tree differed), "unknown" when run without the binary."""
    return os.environ.get(COMMIT_ENV) or "unknown"


# The package (tigris/) and the folder that holds it: its tools run through its dispatcher.
PACKAGE = __name__.split(".")[0]                                  # "tigris"
PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def python_module_command(tool, args=(), env=None, python=None):
    """(argv, env) that run the package's tool (e.g. "sweep") as `python3 -m tigris sweep ARGS`:
    env is a copy of `env` (default os.environ) whose PYTHONPATH starts with the absolute folder
    that holds the package, so the child finds it from any working folder (and on a Slurm node
    sharing the file system). python: the interpreter (default: this one)."""
    env = dict(os.environ if env is None else env)
    rest = env.get("PYTHONPATH", "")
    if rest.split(os.pathsep)[0] != PACKAGE_ROOT:
        env["PYTHONPATH"] = PACKAGE_ROOT + (os.pathsep + rest if rest else "")
    # -P: the working folder does not go first on sys.path (a tigris.py or shlex.py there would
    # shadow the package or the standard library).
    return [python or sys.executable, "-P", "-m", PACKAGE, tool] + [str(a) for a in args], env
