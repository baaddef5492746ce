"""Fixtures for the baseline tests: a small box foot independent of mudrft.feet's shapes."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mudrft.feet.base import Foot, SurfaceElements


class BoxFoot(Foot):
    """Rectangular box with its bottom face at the tip (z = 0 in the foot frame).

    Length along x, width along y, height along z; the bottom face is split into
    ``n x n`` facets, every other face is one facet. Areas are exact, so closed-form
    RFT and area checks hold to rounding.
    """

    name = "box"

    def __init__(
        self, length: float = 0.08, width: float = 0.065, height: float = 0.05, *, n: int = 4
    ) -> None:
        self.length, self.width, self._height, self.n = length, width, height, n

    @property
    def characteristic_length(self) -> float:
        return 0.05

    @property
    def height(self) -> float:
        return self._height

    def elements(self) -> SurfaceElements:
        L, W, H, n = self.length, self.width, self._height, self.n
        xs = (np.arange(n) + 0.5) / n * L - L / 2
        ys = (np.arange(n) + 0.5) / n * W - W / 2
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        cen = [np.stack([gx.ravel(), gy.ravel(), np.zeros(n * n)], 1)]
        nor = [np.tile([0.0, 0.0, -1.0], (n * n, 1))]
        area = [np.full(n * n, L * W / n**2)]
        for c, m, a in (
            ([0, 0, H], [0, 0, 1], L * W),
            ([L / 2, 0, H / 2], [1, 0, 0], W * H),
            ([-L / 2, 0, H / 2], [-1, 0, 0], W * H),
            ([0, W / 2, H / 2], [0, 1, 0], L * H),
            ([0, -W / 2, H / 2], [0, -1, 0], L * H),
        ):
            cen.append(np.array([c], float))
            nor.append(np.array([m], float))
            area.append(np.array([a]))
        return SurfaceElements(np.concatenate(cen), np.concatenate(nor), np.concatenate(area))

    def projected_areas(self, depth: Any) -> np.ndarray:
        d = np.minimum(np.asarray(depth, dtype=float), self._height)
        footprint = np.where(d > 0, self.length * self.width, 0.0)
        return np.stack([d * self.width, d * self.length, footprint], -1)

    def resultant(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        """The flat foot's form (eq. 12) on the box's walls: the faces facing x (area
        ``a_x``) take the normal weight f_n(phi) of sx and the faces facing y the shear
        f_t(pi/2 - phi) of sy, and so on, so that with the mud's one horizontal stress the
        force follows the heading continuously (D9)."""
        a = self.projected_areas(depth)
        s = np.asarray(stress, dtype=float)
        c2 = np.cos(np.asarray(heading, dtype=float)) ** 2
        s2 = 1.0 - c2
        fx = a[..., 0] * c2 * s[..., 0] + a[..., 1] * c2 * s[..., 1]
        fy = a[..., 0] * s2 * s[..., 0] + a[..., 1] * s2 * s[..., 1]
        return np.stack(np.broadcast_arrays(fx, fy, a[..., 2] * s[..., 2]), axis=-1)


@pytest.fixture
def box() -> BoxFoot:
    """An 80 x 65 mm box, 50 mm high (taller than every reference depth)."""
    return BoxFoot()


@pytest.fixture
def make_box() -> type[BoxFoot]:
    """The BoxFoot class, for feet of other sizes."""
    return BoxFoot
