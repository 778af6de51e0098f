"""Test support shared by the test suite (``tests/``) and the benchmarks (``benchmarks/``).

Faces built on known shapes (:mod:`.known_shapes`, :mod:`.rational_faces`, :mod:`.extended_faces`), the seeded
mutation generator and its contract (:mod:`.fuzzing`), faults injected into the reader child
(:mod:`.eval_faults`), the cache and cluster tests' small file set (:mod:`.vault_support`), the checkout's
folders (:mod:`.paths`: the samples and ``../shared/realdata``, defined once) and the command-line outcome
checks (:mod:`.outcomes`).

This is the top of the package's layering (tests/integration/test_layout.py): it may import every wing, and no
module of the package imports it. Importing it loads the standard library only; each submodule imports what it
needs.
"""
