"""Every kind's settings class, each registering itself with ``settings.KIND_SETTINGS`` on
import (``pinn_engine`` imports this first, as meshio's package imports its formats)."""

from pinn_engine.kinds.blocks import settings as _blocks  # noqa: F401
from pinn_engine.kinds.blocks3d import settings as _blocks3d  # noqa: F401
from pinn_engine.kinds.body import settings as _body  # noqa: F401
from pinn_engine.kinds.four_sided import settings as _four_sided  # noqa: F401
from pinn_engine.kinds.hexa import settings as _hexa  # noqa: F401
