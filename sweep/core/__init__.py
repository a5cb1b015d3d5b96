"""The shared core of the Python tools (docs/architecture.md, "The shared core"), one module per
concern as the C++ side has one file each: inputs (read_input, read_text_input,
read_json_input, input_identity), folders (OutFolder, atomic_write), children (spawn,
stop_groups, pool, run_child, the Slurm helpers), flags (--list-flags) and provenance (what
made a figure: its footer). Both languages write one manifest format. Python 3 standard
library only."""
from .base import *  # noqa: F401,F403
from .inputs import *  # noqa: F401,F403
from .folders import *  # noqa: F401,F403
from .children import *  # noqa: F401,F403
from .flags import *  # noqa: F401,F403
from .provenance import *  # noqa: F401,F403
