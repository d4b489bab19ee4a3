"""The names ``slicelab.printing`` re-exports, each from its submodule: read by static tools and by
`slicelab._lazy.attach_stub`, which loads a submodule the first time one of its names is used."""

from .planner import plan as plan, PrintPlan as PrintPlan, layer_bounds as layer_bounds
from .pipeline import layer_paths as layer_paths, plan_layer as plan_layer, STEPS as STEPS
from .table import LayerPaths as LayerPaths
from .config.settings import (
    PrintSettings as PrintSettings,
    GROUPS as GROUPS,
    Extrusion as Extrusion,
    Walls as Walls,
    Infill as Infill,
    Skins as Skins,
    Supports as Supports,
    Motion as Motion,
    Cooling as Cooling,
    Adhesion as Adhesion,
    Machine as Machine,
    Raster as Raster,
    settings_dict as settings_dict,
    setting_names as setting_names,
    FLAVORS as FLAVORS,
)
from .config.printers import (
    PRINTERS as PRINTERS,
    resolve_settings as resolve_settings,
    read_config as read_config,
    format_config as format_config,
)
from .fill import PATTERNS as PATTERNS
from .supports import SUPPORTS as SUPPORTS
from .steps.order import SEAMS as SEAMS
from .roles import KINDS as KINDS, ROLES as ROLES
