"""The shared core of the Python tools (docs/architecture.md, "The shared core"), one module per
concern as the C++ side has one file each: base (limits, names, exceptions, and
python_module_command: the argv and environment that run a tool of the package as
`python3 -m sweep.<tool>`), inputs (read_input, read_text_input,
read_json_input, input_identity), folders (OutFolder, atomic_write), children (spawn,
stop_groups, pool, run_child, the Slurm helpers), flags (--list-flags), provenance (what
made a figure: its footer) and stages (the registration pipeline's stages as the binary lists
them, `tigris register --list-stages`: pipeline_stages(tigris), once per binary and checked;
paper_stages(stages), the paper's rows (title, key, time) with ICP as RPCE and transformation
estimation). Both languages write one manifest format. Python 3 standard
library only."""
from .base import *  # noqa: F401,F403
from .inputs import *  # noqa: F401,F403
from .folders import *  # noqa: F401,F403
from .children import *  # noqa: F401,F403
from .flags import *  # noqa: F401,F403
from .provenance import *  # noqa: F401,F403
from .stages import *  # noqa: F401,F403
