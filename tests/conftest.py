"""Test-session settings: XLA:CPU's fusion emitters are disabled (compile time of the
loop-heavy detection and solver programs drops by about 40 % at equal run time). This changes
no computed value."""

import os

_FLAG = "--xla_cpu_use_fusion_emitters=false"
if _FLAG not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = (os.environ.get("XLA_FLAGS", "") + " " + _FLAG).strip()
