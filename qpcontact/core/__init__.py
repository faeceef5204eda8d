"""(wing docstring: see docs/architecture.md)"""
