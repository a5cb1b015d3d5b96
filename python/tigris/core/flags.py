"""`tigris COMMAND --list-flags` for the Python commands, as the C++ commands print it."""
import argparse, json, sys

ROLES = ("output", "out_folder", "input")


def role(action, what):
    """Marks a path flag (the action add_argument returned) for --list-flags: "output" a file the
    command writes, "out_folder" its output folder, "input" a file or folder it reads."""
    assert what in ROLES, what
    action.tigris_role = what
    return action


def flags_json(parser, command):
    flags = []
    for act in parser._actions:
        longs = [o for o in act.option_strings if o.startswith("--")]
        if not longs:
            continue
        takes = act.nargs != 0
        kind = {int: "INT", float: "FLOAT"}.get(act.type, "TEXT") if takes else ""
        default = act.default if takes and act.default not in (None, argparse.SUPPRESS) else ""
        doc = (act.help or "").replace("%(default)s", str(act.default)).replace("%%", "%")
        flags.append({"flag": longs[0][2:], "takes_value": takes, "type": kind,
                      "default": "" if isinstance(default, list) else str(default), "doc": doc})
        if getattr(act, "tigris_role", None):
            flags[-1]["role"] = act.tigris_role
    return {"command": command, "flags": flags}


def list_flags(parser, command, argv):
    """`tigris COMMAND --list-flags` (alone): prints the flags as JSON and exits 0."""
    if list(argv) == ["--list-flags"]:
        print(json.dumps(flags_json(parser, command), indent=2))
        sys.exit(0)
