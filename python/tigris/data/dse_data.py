"""The pipeline-dse document (`tigris pipeline-dse`'s dse.json) as data: its Pareto points'
names, old and new, the stages' order, and the one reader (report and reproduce read it,
pipeline_dse writes it)."""
import os
import re
from typing import Any

from .. import core

# The Pareto points' names: F1..Fn ("frontier point"). Not DPn: the paper's design points are
# DP1..DP8 (its DP4 and DP7 are the presets dp4 and dp7); not Pn: the sampled points are P001...
PARETO = "F"
OLD_PARETO = re.compile(r"DP(\d+)")   # the names of folders written before the rename


def pareto_name(name: Any) -> Any:
    """A Pareto point's name as written now: an older folder's "DP3" reads "F3" (a name of
    today, an empty one, anything else: unchanged)."""
    m = OLD_PARETO.fullmatch(name) if isinstance(name, str) else None
    return f"{PARETO}{m.group(1)}" if m else name


def pareto_number(name: str) -> int:
    """3 of "F3" (and of an older "DP3"): the Pareto points' order, by time."""
    return int(re.sub(r"^\D+", "", pareto_name(name)))


def renamed(summary: Any) -> Any:
    """A dse.json's summary with its Pareto points under today's names ("dp" of each Pareto
    point and preset: "DP3" -> "F3"), as a copy; anything not a summary is returned as it is.
    A Pareto point's "config" is left alone: it is the path of a file on disk."""
    if not isinstance(summary, dict):
        return summary
    out = dict(summary)
    if isinstance(out.get("dps"), list):
        out["dps"] = [dict(d, dp=pareto_name(d["dp"])) if isinstance(d, dict) and "dp" in d else d
                      for d in out["dps"]]
    if isinstance(out.get("presets"), dict):
        out["presets"] = {k: dict(p, dp=pareto_name(p["dp"])) if isinstance(p, dict) and "dp" in p else p
                          for k, p in out["presets"].items()}
    return out


def stage_order(dse: dict[str, Any]) -> list[str]:
    """The stages' titles in the pipeline's order, as a pipeline-dse's dse.json gives them: its
    "stage_order" (the binary's `tigris register --list-stages`), or in a folder written before
    it had one, the order of the first design point's "stages" (pipeline_dse writes every
    point's in that order). No copy of the list here: a stage added to the pipeline is reported."""
    order = dse.get("stage_order")
    if isinstance(order, list) and all(isinstance(s, str) for s in order):
        return list(order)
    dps = dse.get("dps") if isinstance(dse.get("dps"), list) else []
    return list(next((d["stages"] for d in dps if isinstance(d, dict) and isinstance(d.get("stages"), dict)), {}))


def read_dse(path: str) -> dict[str, Any]:
    """A pipeline-dse folder's dse.json, its Pareto points under today's names (an older
    folder's "DP3" reads "F3": renamed); ValueError naming the file when it is not one."""
    f = os.path.join(path, "dse.json")
    try:
        dse = core.read_json_input(f)
    except core.Refused as e:
        raise ValueError(f"{e} (not a tigris pipeline-dse folder)")
    if not isinstance(dse, dict) or not isinstance(dse.get("dps"), list):
        raise ValueError(f"{f}: no \"dps\" list: not written by tigris pipeline-dse")
    order = dse.get("stage_order", [])
    if not (isinstance(order, list) and all(isinstance(s, str) for s in order) and len(set(order)) == len(order)):
        raise ValueError(f"{f}: \"stage_order\" is not a list of distinct stage titles: not written by tigris "
                         "pipeline-dse")
    return renamed(dse)
