"""The judge: every answer certified from the problem data, whatever a method
says — componentwise scales, the LCP and QP certificates, ``certify`` for every
kind.  Imports no method (docs/architecture.md)."""
