"""What the certificates with a forward-error estimate share: the estimate
computed on first use (for a large active block or Jacobian it costs one more
factorization, which a solve should not pay unasked) and kept once computed,
also across pickling."""

from __future__ import annotations

from dataclasses import fields

from .doubt import doubt, no_digit

__all__ = ["ForwardErrorMixin"]


class ForwardErrorMixin:
    """For a frozen dataclass with an ``error`` field and a ``_forward`` field
    holding (condition, forward_error) or a function computing them."""

    @property
    def condition(self) -> float:
        return self._forward_pair()[0]

    @property
    def forward_error(self) -> float:
        return self._forward_pair()[1]

    @property
    def forward_error_known(self) -> bool:
        """Whether the forward error is already computed (small problems:
        always; large ones: once asked for)."""
        return not callable(self._forward)

    def _forward_pair(self) -> tuple[float, float]:
        if callable(self._forward):
            object.__setattr__(self, "_forward", self._forward())
        return self._forward

    def __getstate__(self):
        self._forward_pair()
        if callable(getattr(self, "_near", None)):
            # a function does not pickle: its value (None unless asked for)
            object.__setattr__(self, "_near", self._near() if not self.forward_error < 1.0 else None)
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)

    def ok(self, tol: float) -> bool:
        """The backward error meets ``tol``, nothing casts doubt on it and a
        digit is guaranteed (:mod:`qpcontact.judge.doubt`)."""
        return bool(self.error <= tol) and doubt(self, tol) is None and no_digit(self) is None

    def as_dict(self) -> dict:
        d = {f.name: getattr(self, f.name) for f in fields(self) if not f.name.startswith("_")}
        d["condition"], d["forward_error"] = self._forward_pair()[:2]
        return d
