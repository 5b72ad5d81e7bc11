"""The complete second-order solver in shards (shards.py): the 2^s homotopy
paths tracked as independent tasks on any executor (libkin.parallel) and
merged into exactly the result of one call."""
from .shards import available, equivariant_form, orbit_task, range_task, shard_ranges, solve_sharded

__all__ = ["solve_sharded", "available", "equivariant_form", "shard_ranges", "range_task", "orbit_task"]
