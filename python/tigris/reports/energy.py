"""The paper's section 6 energy and area measured (docs/model.md, §14)."""
from ..data import evaldata as ed
from ..data.evaldata import num
from .evaluation import nc_rows, opt_pair
from .claims import (Claim, NO_CHANGE, PAPER, SPLIT_NAMES, label, pct, per_search, searches, up, within_2x,
                     within_2x_gain, xf)


# ------------------------------------------------------------------------- section 14 claims
# One small function per claim: each takes the sweep and gives its Claim records (per search
# setting where the paper's claim is per search), the missing one naming the rows it needs.

SPLIT_HOW = ("share of `energy_pj.<part>` in `energy_pj.total`, default configuration, exact "
             "search (the first search present, NN preferred); the paper's split is DP4's (NN and "
             "radius 0.30 searches). Direction: the part has the same rank among the five as in "
             "the paper.")


def default_row(sw):
    """The default configuration's row of the first search present (NN preferred), or None."""
    return next((r for r in (ed.find(sw.ok, **s) for s in searches(sw.ok)) if r is not None), None)


def split_fact(sw, default, p):
    """The measured fact behind a part's share of the energy."""
    if p == "dram":
        wb = num(default, "buffers.dram.write_bytes") or 0
        return (f"{ed.fmt_bytes(wb)} of results written to DRAM at "
                f"{(num(default, 'energy_pj.dram') or 0) / wb if wb else 0:.0f} pJ/byte")
    if p == "pe":
        q = num(default, "queries") or 1
        pe = sum(num(default, f"visits.{k}") or 0 for k in ("leaf_points", "leader_checks", "follower_points"))
        return f"{pe / q:.0f} PE distances per query"
    if p == "leakage":
        return f"{num(default, 'area_mm2.total') or 0:.2f} mm2 over {num(default, 'cycles'):,.0f} cycles"
    return f"all on-chip traffic {ed.fmt_bytes(sum(ed.buffer_traffic(default, sw.columns).values()))}"


def claims_split(sw):
    """The paper's energy split: each part's share and its rank among the five."""
    default = default_row(sw)
    if default is None or not num(default, "energy_pj.total"):
        return [Claim("split", "14", "energy split PE 53.7%, SRAM read 34.8%, write 8.0%, leakage 3.3%, DRAM 0.2%",
                      "53.7/34.8/8.0/3.3/0.2%", SPLIT_HOW).missing("a default-configuration row")]
    tot = num(default, "energy_pj.total")
    shares = {p: (num(default, f"energy_pj.{p}") or 0) / tot for p in SPLIT_NAMES}
    rank_m = sorted(shares, key=lambda p: -shares[p])
    rank_p = sorted(PAPER["split"], key=lambda p: -PAPER["split"][p])
    others = {p: (num(default, f"energy_pj.{p}") or 0) / tot for p in ("ru", "node_cache", "leader_buffer")}
    out = []
    for p, name in SPLIT_NAMES.items():
        fact = (f"{split_fact(sw, default, p)}; rank {rank_m.index(p) + 1} of 5 (paper {rank_p.index(p) + 1}); "
                f"parts the paper's split does not name: RU {pct(others['ru'])}, Node Cache "
                f"{pct(others['node_cache'])}, Leader Buffer {pct(others['leader_buffer'])}")
        c = Claim(f"split-{p}", "14", f"energy split: {name} ({label(default['eff'])}, default machine)",
                  pct(PAPER["split"][p]), SPLIT_HOW)
        out.append(c.set(pct(shares[p]), rank_m.index(p) == rank_p.index(p),
                         within_2x(shares[p], PAPER["split"][p]), fact))
    return out


def claims_acckd_energy(sw):
    """Acc-KD against Acc-2SKD: the energy ratio."""
    how = "energy_pj.total of Acc-KD (`height` full) / of Acc-2SKD (height 10), exact search."

    def measure(s, kd, two):
        ek, e2 = num(kd, "energy_pj.total"), num(two, "energy_pj.total")
        v = ek / e2
        diffs = sorted(((num(kd, f"energy_pj.{p}") or 0) - (num(two, f"energy_pj.{p}") or 0), p)
                       for p in ("pe", "ru", "sram_read", "sram_write", "node_cache", "dram", "leakage"))
        c = Claim(f"acckd-energy-{s['mode']}", "14", f"Acc-KD uses more energy than Acc-2SKD "
                  f"({label(s)}; energy ratio)", f"{PAPER['acckd_energy']:g}x", how)
        return c.set(xf(v), up(v), within_2x_gain(v, PAPER["acckd_energy"]),
                     f"{ek / 1e6:,.1f} vs {e2 / 1e6:,.1f} uJ; cycles {num(kd, 'cycles') / num(two, 'cycles'):.2f}x; "
                     "largest changes: " + ", ".join(f"{p} {d / 1e6:+,.1f} uJ" for d, p in (diffs[0], diffs[-1])) +
                     f"; DRAM {pct((num(two, 'energy_pj.dram') or 0) / e2)} of Acc-2SKD's energy")
    return per_search(searches(sw.ok), lambda s: (ed.find(sw.ok, height=ed.CANONICAL, **s),
                                                   ed.find(sw.ok, height=10, **s)), measure,
                      Claim("acckd-energy", "14", "Acc-KD uses ~2.5x the energy of Acc-2SKD", "2.5x", how)
                      .missing("rows at `height` full and 10"))


def claims_mqmn_power(sw):
    """MQMN against MQSN(+Forward): the power ratio."""
    how = "power_w with be.issue_policy=mqmn / with mqsn (+Forward), exact search, top height 10."

    def measure(s, a, b):
        v = num(b, "power_w") / num(a, "power_w")
        c = Claim(f"mqmn-power-{s['mode']}", "14", f"MQMN draws more power than MQSN(+Forward) "
                  f"({label(s)}; power ratio)", f"{PAPER['mqmn_power']:g}x", how)
        return c.set(xf(v), up(v), within_2x_gain(v, PAPER["mqmn_power"]),
                     f"power ratio = energy ratio {num(b, 'energy_pj.total') / num(a, 'energy_pj.total'):.2f}x "
                     f"x speed-up {num(a, 'cycles') / num(b, 'cycles'):.2f}x; SRAM read energy "
                     f"{(num(a, 'energy_pj.sram_read') or 0) / 1e6:,.1f} -> "
                     f"{(num(b, 'energy_pj.sram_read') or 0) / 1e6:,.1f} uJ; "
                     f"DRAM {pct((num(a, 'energy_pj.dram') or 0) / num(a, 'energy_pj.total'))} of MQSN's energy")
    return per_search(searches(sw.ok), opt_pair(sw, "+Forward", "MQMN"), measure,
                      Claim("mqmn-power", "14", "MQMN ~4x the power of MQSN(+Forward)", "4x", how)
                      .missing("the +Forward and MQMN rows"))


def claims_nc_energy(sw):
    """The Node Cache's energy saving."""
    how = "1 - energy_pj.total with the default Node Cache / with node_cache.bytes 0, height 10."

    def measure(s, w, wo):
        v = 1 - num(w, "energy_pj.total") / num(wo, "energy_pj.total")
        c = Claim(f"nc-energy-{s['mode']}", "14", f"the Node Cache saves energy ({label(s)})",
                  pct(PAPER["nc_energy_saving"]), how)
        return c.set(pct(v), v > NO_CHANGE, within_2x(v, PAPER["nc_energy_saving"]),
                     f"Point Buffer energy {(num(wo, 'energy_pj.by_unit.points') or 0) / 1e6:,.1f} -> "
                     f"{(num(w, 'energy_pj.by_unit.points') or 0) / 1e6:,.1f} uJ, Node Cache "
                     f"{(num(w, 'energy_pj.node_cache') or 0) / 1e6:,.1f} uJ, leakage "
                     f"{(num(wo, 'energy_pj.leakage') or 0) / 1e6:,.2f} -> "
                     f"{(num(w, 'energy_pj.leakage') or 0) / 1e6:,.2f} uJ; "
                     f"DRAM {pct((num(w, 'energy_pj.dram') or 0) / num(w, 'energy_pj.total'))} of the total")
    return per_search(searches(sw.ok), lambda s: nc_rows(sw, s), measure,
                      Claim("nc-energy", "14", "the Node Cache saves 5.9% energy", "5.9%", how)
                      .missing("rows with `node_cache.bytes` 0 and the default at height 10"))


def claims_area(sw):
    """The area of the default machine against the paper's (the table is calibrated to it)."""
    how = ("`area_mm2.sram` and `.logic` of the default configuration; the area table is "
           "calibrated to these two totals (docs/model.md), so this checks the calibration, not a trend.")
    default = default_row(sw)
    if default is None or num(default, "area_mm2.sram") is None:
        return [Claim("area", "14", "area 8.38 mm2 SRAM, 7.19 mm2 logic", "8.38 / 7.19 mm2", how)
                .missing("a default-configuration row")]
    out = []
    for part, key in (("sram", "area_sram"), ("logic", "area_logic")):
        v = num(default, f"area_mm2.{part}")
        c = Claim(f"area-{part}", "14", f"area: {part.upper() if part == 'sram' else part} (16 nm)",
                  f"{PAPER[key]:.2f} mm2", how)
        out.append(c.set(f"{v:.2f} mm2", None, within_2x(v, PAPER[key]),
                         "calibrated default (the table's densities are fitted to the paper's totals)"))
    return out


def claims_energy(sw):
    """The section-14 claims, in the report's order."""
    return [c for f in (claims_split, claims_acckd_energy, claims_mqmn_power, claims_nc_energy, claims_area)
            for c in f(sw)]
