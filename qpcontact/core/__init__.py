"""Vocabulary and problem types: exceptions, the accuracy ladder, statuses and result
types, LCP/ParametricLCP and their validation, exact LCP/QP conversions, the
linear algebra of active blocks, option checks and file, progress and cluster
utilities.  Imports nothing of qpcontact's but itself (docs/architecture.md)."""
