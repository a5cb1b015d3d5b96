"""What made a figure: every figure the tools draw carries a footer, one or two lines
of small grey text under its axes, with the command line that made its data, the inputs'
identity (path and SHA-256), a digest of the settings and the tigris commit. The C++ twin, for
text outputs: provenance_json / provenance_lines (testbench/run_inputs.*).

    prov = provenance(folder)              # the data's maker, from folder/manifest.json
    add_footer(fig, footer_lines(prov))    # last, after every other layout call

Standard library only: matplotlib is touched through the figure given to add_footer."""
import hashlib, json, os, shlex
from .base import MANIFEST, MAX_SETTINGS_BYTES, Refused, tigris_commit
from .inputs import input_identity, read_json_input

FOOTER_GID = "tigris-footer"    # the footer's Text (gid: its group's id in an SVG)
FOOTER_POINTS = 6.5             # font size
FOOTER_COLOR = "0.45"
SEP = " \u00b7 "                # between the parts of a line
ELLIPSIS = "\u2026"
MIN_PATH = 24                   # a path is shortened in its middle down to this many characters
MAX_LISTED = 3                  # more file inputs than this are summed up in one digest


def digest(obj):
    """Hex SHA-256 of obj as JSON with sorted keys and no spaces (nlohmann's dump() of the same
    object gives the same text for strings, integers and booleans)."""
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(text.encode("utf-8", "backslashreplace")).hexdigest()


def command_text(argv):
    """A command line as a shell would take it, the program by its name alone (the commit says
    which build it was): ["/x/build/bin/tigris", "odometry", "--out", "a b"] ->
    "tigris odometry --out 'a b'"."""
    argv = [str(a) for a in argv]
    if not argv:
        return ""
    return shlex.join([os.path.basename(argv[0]) or argv[0]] + argv[1:])


def provenance(folder=None, argv=None, command=None, files=()):
    """What made a figure's data, as a dict:
      argv          the command that made it: folder/manifest.json's argv, else argv (a tool's
                    own command line) when given, else None; command_line: as one text
      commit        the manifest's "commit", else $TIGRIS_COMMIT, else "unknown"
      inputs        the manifest's inputs ({role, path, bytes, sha256} or {role, builtin})
      settings      the manifest's settings, config_sha256 their digest() (None without)
      files         {path, sha256} of the data files the figure reads (files: paths)
      folder, note  the folder, and why its manifest was not used (missing, unreadable, of
                    another command than `command`), else None.
    Never raises for a missing or bad manifest: a figure is still drawn, and says so."""
    p = {"folder": os.path.abspath(folder) if folder else None, "argv": None, "command_line": None, "commit": None,
         "inputs": [], "settings": None, "config_sha256": None, "files": [], "note": None}
    m = None
    if folder:
        path = os.path.join(folder, MANIFEST)
        if not os.path.lexists(path):
            p["note"] = f"no {MANIFEST} in {p['folder']}"
        else:
            try:
                m = read_json_input(path, "the folder's manifest")
            except Refused:
                p["note"] = f"{path}: not a readable manifest"
            if m is not None and not (isinstance(m, dict) and m.get("tigris_manifest") == 1):
                m, p["note"] = None, f"{path}: not a manifest of tigris"
            elif m is not None and command and m.get("command") != command:
                p["note"] = f"{path} is of tigris {m.get('command')}, not of tigris {command}"
                m = None
    if m is not None:
        if isinstance(m.get("argv"), list) and m["argv"]:
            p["argv"] = [str(a) for a in m["argv"]]
        p["inputs"] = [i for i in m["inputs"] if isinstance(i, dict)] if isinstance(m.get("inputs"), list) else []
        if "settings" in m:
            p["settings"] = m["settings"]
            p["config_sha256"] = digest(m["settings"])
        if isinstance(m.get("commit"), str) and m["commit"]:
            p["commit"] = m["commit"]
    if p["argv"] is None and argv:
        p["argv"] = [str(a) for a in argv]
    p["command_line"] = command_text(p["argv"]) if p["argv"] else None
    p["commit"] = p["commit"] or tigris_commit()
    for f in files:
        try:
            ident = input_identity("data", f, "a figure's data", MAX_SETTINGS_BYTES)
            p["files"].append({"path": ident["path"], "sha256": ident["sha256"]})
        except Refused:
            p["files"].append({"path": os.path.abspath(f), "sha256": None})
    return p


def _sha(h):
    return f"sha256 {h[:12]}" if h else "sha256 unknown"


def inputs_text(inputs):
    """The inputs in a few words: up to MAX_LISTED files each as "role path (sha256 12hex)"
    (the C++ provenance_lines' form), more as "N inputs in FOLDER, sha256 of their sha256s
    12hex": the SHA-256 of their SHA-256 hex digests, one a line in the manifest's order."""
    out, hashed = [], []
    for i in inputs:
        role = str(i.get("role", "input"))
        if "builtin" in i:
            out.append(f"{role} {i['builtin']}, built in")
        elif "same_as" in i:
            out.append(f"{role} the {i['same_as']} itself")
        elif i.get("path"):
            hashed.append(i)
    if len(hashed) <= MAX_LISTED:
        out += [f"{i.get('role', 'input')} {i['path']} ({_sha(i.get('sha256'))})" for i in hashed]
    else:
        try:
            where = os.path.commonpath([str(i["path"]) for i in hashed])
        except ValueError:                       # absolute and relative mixed
            where = ""
        joint = hashlib.sha256("".join(f"{i.get('sha256') or ''}\n" for i in hashed).encode()).hexdigest()
        out.append(f"{len(hashed)} inputs" + (f" in {where}" if where not in ("", "/") else "")
                   + f", sha256 of their sha256s {joint[:12]}")
    return out


def _identity(p):
    parts = [f"{f['path']} ({_sha(f['sha256'])})" for f in p["files"]] + inputs_text(p["inputs"])
    if p["config_sha256"]:
        parts.append(f"settings {_sha(p['config_sha256'])}")
    return parts


def _maker(p):
    return p["command_line"] or f"an unrecorded command ({p['note'] or 'no manifest'})"


def footer_lines(made, drawn=None, details=()):
    """The footer's lines, of parts joined by SEP (add_footer flows the parts into the figure's
    width, at most two lines).
    Alone (the figure is drawn by the command that made its data, e.g. tigris odometry):
      "made by <its command line>"
      "commit <c> · <details> · <inputs> · settings sha256 <d>"
    With drawn (the provenance of a tool drawing others' data, e.g. tigris plot of sweeps;
    made may then be a list, one per data folder):
      "drawn by <its command line> · commit <c> · <details>"
      "from <file> (sha256 <h>), made by <command line> (commit <c>; <inputs>; settings sha256 <d>); ..."
    details: short texts the figure's tool adds (preset, back-end, seed)."""
    made = made if isinstance(made, list) else [made]
    if drawn is None:
        p = made[0]
        return [f"made by {_maker(p)}", SEP.join([f"commit {p['commit']}"] + list(details) + _identity(p))]
    first = SEP.join([f"drawn by {_maker(drawn)}", f"commit {drawn['commit']}"] + list(details))
    data = []
    for p in made:
        files = ", ".join(f"{f['path']} ({_sha(f['sha256'])})" for f in p["files"])
        rest = [f"commit {p['commit']}"] + inputs_text(p["inputs"]) + \
            ([f"settings {_sha(p['config_sha256'])}"] if p["config_sha256"] else [])
        maker = f"made by {p['command_line']} ({'; '.join(rest)})" if p["command_line"] else f"({_maker(p)})"
        data.append(f"{files}, {maker}" if files else maker)
    return [first, "from " + "; ".join(data)]


def shorten(text, n):
    """text in at most n characters, its middle replaced by an ellipsis (of a path the end, its
    file name, is kept longer than the start)."""
    if len(text) <= n:
        return text
    if n < 2:
        return text[:n]
    head = (n - 1) // 3
    return text[:head] + ELLIPSIS + text[len(text) - (n - 1 - head):]


def fit_line(line, n):
    """line in at most n characters: its paths (words with a /) shortened in their middle first,
    the longest first and none below MIN_PATH characters, then whole words taken out of its
    middle (one ellipsis for them), then the characters in its middle."""
    words = line.split(" ")
    over = len(line) - n
    paths = [i for i, w in enumerate(words) if "/" in w and len(w) > MIN_PATH]
    if over > 0 and paths:
        cap = max(len(words[i]) for i in paths)          # the longest down to the next, and so on
        while cap > MIN_PATH and sum(max(0, len(words[i]) - cap) for i in paths) < over:
            cap -= 1
        for i in paths:
            words[i] = shorten(words[i], cap)
    a = b = len(words) // 2                              # then words from the middle, whole
    while len(" ".join(words)) > n and (a > 1 or b < len(words) - 1):
        cut = words[:a] + [ELLIPSIS] + words[b:]
        if len(" ".join(cut)) <= n:
            return " ".join(cut)
        a, b = (a - 1, b) if (b - a) % 2 == 0 and a > 1 or b >= len(words) - 1 else (a, b + 1)
    return shorten(" ".join(words), n)


def footer_text(fig):
    """The text of fig's footer, None without one (for the tests)."""
    for t in fig.texts:
        if t.get_gid() == FOOTER_GID:
            return t.get_text()
    return None


def flow(lines, n, max_lines=2):
    """The parts of lines (texts of parts joined by SEP) in at most max_lines lines of at most n
    characters: each part on the line so far when it fits there, else on the next; the last
    line takes all the rest, and any line too long is shortened by fit_line."""
    parts = [part for line in lines for part in str(line).split(SEP) if part]
    out, cur = [], None
    for i, part in enumerate(parts):
        if cur is not None and len(cur) + len(SEP) + len(part) <= n:
            cur += SEP + part
            continue
        if cur is not None:
            out.append(cur)
        if len(out) == max_lines - 1:                    # the last line: all the rest
            cur = SEP.join(parts[i:])
            break
        cur = part
    if cur is not None:
        out.append(cur)
    return [fit_line(line, n) for line in out]


def add_footer(fig, lines, max_lines=2):
    """Writes lines (footer_lines) in small grey text at the bottom of fig, their parts flowed
    into at most max_lines lines that fit the figure's width (flow), and lays the figure out
    above them (tight_layout in the rest of the figure): call it last, after any other layout,
    before saving. A second call replaces the footer. Returns the footer's Text, None without
    lines."""
    from matplotlib.font_manager import FontProperties
    for t in list(fig.texts):
        if t.get_gid() == FOOTER_GID:
            t.remove()
    lines = [str(line) for line in lines if line]
    if not lines:
        return None
    w_in, h_in = fig.get_size_inches()
    side = 6.0                                             # margin each side, points
    room = w_in * 72.0 - 2 * side
    renderer = fig.canvas.get_renderer() if hasattr(fig.canvas, "get_renderer") else None
    prop = FontProperties(size=FOOTER_POINTS)

    def width(text):                                       # in points
        if renderer is None:
            return len(text) * FOOTER_POINTS * 0.62
        return renderer.get_text_width_height_descent(text, prop, ismath=False)[0] * 72.0 / fig.dpi
    whole = SEP.join(lines)
    n = max(8, int(len(whole) * room / max(width(whole), 1.0)))   # characters a line holds, about
    fitted = flow(lines, n, max_lines)
    while n > 8 and max(width(line) for line in fitted) > room:
        n = max(8, n - max(1, n // 40))
        fitted = flow(lines, n, max_lines)
    bottom = 3.0                                           # points below the text
    block = bottom + len(fitted) * FOOTER_POINTS * 1.25 + 4.0
    t = fig.text(side / (w_in * 72.0), bottom / (h_in * 72.0), "\n".join(fitted), fontproperties=prop,
                 color=FOOTER_COLOR, ha="left", va="bottom", linespacing=1.25, gid=FOOTER_GID)
    fig.tight_layout(rect=(0, block / (h_in * 72.0), 1, 1))
    return t
