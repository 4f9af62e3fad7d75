"""The wave-generator balls' radial springs in the contact problems: the block they add to the
balls' flexibility (:func:`spring_block`) and the load each spring carries (:func:`ball_totals`).
A candidate ball is its own ball, or, in the axial slices of :mod:`profilegen.contact.face_curve`,
a share of one ball (``ball_body``): the shares' reactions add up on the one spring."""

from __future__ import annotations

import numpy as np

__all__ = ["ball_totals", "spring_block"]


def spring_block(ball_compliance, act, ball_body=None) -> np.ndarray:
    """The active candidates' spring compliances (mm/N, |act| × |act|): each ball's c on the
    diagonal and, where candidates are shares of one ball (``ball_body``, the axial slices of
    :mod:`profilegen.contact.face_curve`), c between them too — one ball approaches by c·ΣR
    under the reactions R of all its shares."""
    c = np.asarray(ball_compliance, dtype=float)[act]
    if ball_body is None:
        return np.diag(c)
    body = np.asarray(ball_body)[act]
    return np.where(body[:, None] == body[None, :], 0.5 * (c[:, None] + c[None, :]), 0.0)


def ball_totals(reactions_n, ball_body=None) -> np.ndarray:
    """Each candidate's ball load (N): its own reaction, or with ``ball_body`` the sum over the
    shares of its ball (the load its Hertz contacts carry)."""
    r = np.asarray(reactions_n, dtype=float)
    if ball_body is None:
        return r
    body = np.asarray(ball_body)
    return np.bincount(body, weights=r)[body]
