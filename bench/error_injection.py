#!/usr/bin/python3
"""Error tolerance of the registration pipeline (the paper's section "Quantifying the
error-tolerance", Figure 5): registration error as injected KD-tree search error grows.

Runs `tigris register` (preset DP4, exact golden search by default) with
  --inject-kth K        RPCE's NN searches return the K-th nearest neighbour, K in 1 2 4 8 16 32
  --inject-shell R1,R2  normal estimation's radius searches return R1 <= d <= R2 instead of
                        d <= r; the shells are fixed multiples of the preset's r (for DP4's
                        r = 0.30: 0.05-0.35, 0.10-0.40, 0.15-0.45, 0.20-0.50, 0.25-0.60)
on the built-in synthetic pair and, when DIR/000000.bin, 000001.bin and poses.txt exist
(--kitti, default ../shared/data/kitti-00), on KITTI 00 frame 1 into frame 0 (ground truth from
poses.txt). Prints the translation and rotation error tables (markdown), writes OUT/results.csv
and, with Debian's python3-matplotlib, OUT/error_vs_k.png and OUT/error_vs_shell.png.
Run it with Debian's /usr/bin/python3 (the shebang), where python3-matplotlib installs.
Usage: bench/error_injection.py [--tigris build/bin/tigris] [--kitti DIR] [--out DIR]
                                [--preset dp4] [--search exact] [--no-kitti]
"""
import argparse, csv, json, os, subprocess, sys, tempfile, time

KS = [1, 2, 4, 8, 16, 32]
# Shells as multiples of the normal radius r: (R1 / r, R2 / r), every one R1 < r < R2.
SHELLS = [(1 / 6, 7 / 6), (1 / 3, 4 / 3), (1 / 2, 3 / 2), (2 / 3, 5 / 3), (5 / 6, 2.0)]
PRESET_RADIUS = {"dp4": 0.30, "dp7": 0.75}


def register(tigris, pair_args, extra, out, preset, search):
    cmd = [tigris, "register", "--preset", preset, "--search", search, "--out", out] + pair_args + extra
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("failed: " + " ".join(cmd) + "\n" + p.stdout + p.stderr)
    with open(os.path.join(out, "registration.json")) as f:
        doc = json.load(f)
    e = doc["error"]
    return {"translation_m": e["translation_m"], "rotation_deg": e["rotation_deg"],
            "icp_iterations": doc["stages"]["icp"]["iterations"],
            "normals_neighbors": doc["stages"]["normals"]["neighbors"],
            "seconds": time.time() - t0}


def shell_label(r1, r2):
    return f"{r1:.2f}-{r2:.2f}"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tigris", default=os.path.join(here, "..", "build", "testbench", "tigris"))
    ap.add_argument("--kitti", default=os.path.join(here, "..", "..", "shared", "data", "kitti-00"))
    ap.add_argument("--no-kitti", action="store_true", help="the synthetic pair only")
    ap.add_argument("--out", default="error-injection-out")
    ap.add_argument("--preset", default="dp4", choices=sorted(PRESET_RADIUS))
    ap.add_argument("--search", default="exact", choices=["exact", "flann"])
    a = ap.parse_args()
    if not os.access(a.tigris, os.X_OK):
        sys.exit(f"no tigris binary at {a.tigris} (build it, or give --tigris)")
    os.makedirs(a.out, exist_ok=True)
    r = PRESET_RADIUS[a.preset]
    shells = [(round(f1 * r, 4), round(f2 * r, 4)) for f1, f2 in SHELLS]

    pairs = [("synthetic", [])]
    k0, k1, poses = (os.path.join(a.kitti, n) for n in ("000000.bin", "000001.bin", "poses.txt"))
    if not a.no_kitti and all(os.path.exists(p) for p in (k0, k1, poses)):
        pairs.append(("KITTI 00 1->0", ["--source", k1, "--target", k0, "--kitti-poses", poses,
                                        "--kitti-frames", "1,0"]))
    elif not a.no_kitti:
        print(f"(KITTI 00 not found at {a.kitti}: the synthetic pair only)\n", file=sys.stderr)

    tmp = tempfile.mkdtemp(prefix="error_injection_")
    rows = []  # (pair, kind, label, x, result)
    for name, args in pairs:
        for k in KS:
            extra = [] if k == 1 else ["--inject-kth", str(k)]
            print(f"{name}: K = {k}", file=sys.stderr, flush=True)
            rows.append((name, "k", str(k), k, register(a.tigris, args, extra, tmp, a.preset, a.search)))
        base = next(x for x in rows if x[0] == name and x[1] == "k" and x[3] == 1)[4]
        rows.append((name, "shell", f"none (ball r = {r:.2f})", 0, base))
        for i, (r1, r2) in enumerate(shells, 1):
            print(f"{name}: shell {r1}..{r2}", file=sys.stderr, flush=True)
            res = register(a.tigris, args, ["--inject-shell", f"{r1},{r2}"], tmp, a.preset, a.search)
            rows.append((name, "shell", shell_label(r1, r2), i, res))

    with open(os.path.join(a.out, "results.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["pair", "preset", "search", "injection", "value", "translation_m", "rotation_deg",
                    "icp_iterations", "normals_neighbors", "seconds"])
        for name, kind, label, _, res in rows:
            w.writerow([name, a.preset, a.search, kind, label, f"{res['translation_m']:.6f}",
                        f"{res['rotation_deg']:.6f}", res["icp_iterations"], res["normals_neighbors"],
                        f"{res['seconds']:.2f}"])

    names = [n for n, _ in pairs]
    print(f"## Error injection, preset {a.preset} (normal radius r = {r:.2f} m), {a.search} search\n")
    for kind, title, head in (("k", "RPCE returns the K-th nearest neighbour", "K"),
                              ("shell", "normal estimation searches the shell R1..R2 (m) instead of the ball r",
                               "R1-R2")):
        print(f"### {title}\n")
        print(f"| {head} | " + " | ".join(f"{n} translation (m) | {n} rotation (deg)" for n in names) + " |")
        print("|---|" + "---:|---:|" * len(names))
        labels = [x[2] for x in rows if x[0] == names[0] and x[1] == kind]
        for label in labels:
            cells = []
            for n in names:
                res = next(x[4] for x in rows if x[0] == n and x[1] == kind and x[2] == label)
                cells.append(f"{res['translation_m']:.4f} | {res['rotation_deg']:.4f}")
            print(f"| {label} | " + " | ".join(cells) + " |")
        print()
    print(f"wrote {os.path.join(a.out, 'results.csv')}")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"no matplotlib for {sys.executable}: no plots (Debian: apt-get install python3-matplotlib, "
              "and run this script with /usr/bin/python3, its shebang)")
        return
    for kind, fname, xlabel in (("k", "error_vs_k.png", "K (RPCE returns the K-th nearest neighbour)"),
                                ("shell", "error_vs_shell.png",
                                 f"normal-estimation shell R1-R2 (m), instead of the ball r = {r:.2f} m")):
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        for n in names:
            sel = [x for x in rows if x[0] == n and x[1] == kind]
            xs = list(range(len(sel)))
            axes[0].plot(xs, [x[4]["translation_m"] for x in sel], marker="o", label=n)
            axes[1].plot(xs, [x[4]["rotation_deg"] for x in sel], marker="o", label=n)
        ticks = [x[2] if kind == "k" else x[2].split(" (")[0] for x in rows if x[0] == names[0] and x[1] == kind]
        for ax, ylabel in zip(axes, ("translation error (m)", "rotation error (deg)")):
            ax.set_xticks(range(len(ticks)))
            ax.set_xticklabels(ticks, rotation=0 if kind == "k" else 30)
            ax.set_xlabel(xlabel, fontsize=8)
            ax.set_ylabel(ylabel)
            ax.set_ylim(bottom=0)
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=8)
        fig.suptitle(f"Registration error vs injected KD-tree search error ({a.preset}, {a.search})")
        fig.tight_layout()
        path = os.path.join(a.out, fname)
        fig.savefig(path, dpi=120)
        plt.close(fig)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
