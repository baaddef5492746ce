"""Which papers a run relied on: modules :func:`register` what they use, :func:`citations`
lists it as BibTeX."""

from __future__ import annotations

__all__ = ["BIBTEX", "citations", "register", "reset"]

#: BibTeX entries of the works mudrft implements or compares with.
BIBTEX: dict[str, str] = {
    "chen2026mud": """@article{chen2026mud,
  author = {Chen, Xunjie and Wang, Liuyin and Huang, Xinyan and Shan, Jerry and Shen, Yantao and Yi, Jingang},
  title = {A Foot Resistive Force Model for Legged Locomotion on Muddy Terrains},
  year = {2026},
  note = {Preprint with supplementary materials; the model implemented by mudrft}
}""",
    "li2013terradynamics": """@article{li2013terradynamics,
  author = {Li, Chen and Zhang, Tingnan and Goldman, Daniel I.},
  title = {A Terradynamics of Legged Locomotion on Granular Media},
  journal = {Science},
  volume = {339},
  number = {6126},
  pages = {1408--1412},
  year = {2013},
  doi = {10.1126/science.1229163}
}""",
    "godon2022ral": """@article{godon2022ral,
  author = {Godon, Simon and Ristolainen, Asko and Kruusmaa, Maarja},
  title = {An Insight on Mud Behavior Upon Stepping},
  journal = {IEEE Robotics and Automation Letters},
  year = {2022},
  note = {Linear stiffness mud model, cited as [GodonRAL2022] by Chen et al. 2026}
}""",
    "liu2023ral": """@article{liu2023ral,
  author = {Liu, Shipeng and Huang, Boyuan and Qian, Feifei},
  title = {Adaptation of Flipper-Mud Interactions Enables Effective Terrestrial Locomotion on Muddy Substrates},
  journal = {IEEE Robotics and Automation Letters},
  year = {2023},
  note = {Cited as [liuRAL2023adaptation] by Chen et al. 2026}
}""",
    "chen2024aim": """@misc{chen2024aim,
  author = {Chen, Xunjie and Yi, Jingang and Shan, Jerry},
  title = {A Reduced-Order Resistive Force Model for Robotic Foot-Mud Interactions},
  year = {2024},
  note = {arXiv:2403.02617; IEEE/ASME AIM 2024; identified as [ChenAIM24] of Chen et al. 2026 by title,
          authors and topic. mudrft's MaxwellMud is a reconstruction from its abstract and the 2026 paper}
}""",
    "treers2021granular": """@article{treers2021granular,
  author = {Treers, Laura K. and Cao, Cyndia and Stuart, Hannah S.},
  title = {Granular Resistive Force Theory Implementation for Three-Dimensional Trajectories},
  journal = {IEEE Robotics and Automation Letters},
  volume = {6},
  number = {2},
  pages = {1887--1894},
  year = {2021},
  doi = {10.1109/LRA.2021.3057052}
}""",
    "agarwal2023rft3d": """@article{agarwal2023rft3d,
  author = {Agarwal, Shashank and Goldman, Daniel I. and Kamrin, Ken},
  title = {Mechanistic framework for reduced-order models in soft materials: Application to three-dimensional granular intrusion},
  journal = {Proceedings of the National Academy of Sciences},
  volume = {120},
  pages = {e2214017120},
  year = {2023},
  doi = {10.1073/pnas.2214017120},
  note = {3D-RFT; arXiv:2205.14920. mudrft's GranularRFT3D; its fit coefficients were read from public
          implementations, not from the supplementary table (see docs/model.md, D91)}
}""",
    "todorov2012mujoco": """@inproceedings{todorov2012mujoco,
  author = {Todorov, Emanuel and Erez, Tom and Tassa, Yuval},
  title = {MuJoCo: A Physics Engine for Model-Based Control},
  booktitle = {IEEE/RSJ International Conference on Intelligent Robots and Systems (IROS)},
  pages = {5026--5033},
  year = {2012}
}""",
}

_used: dict[str, None] = {}


def register(key: str) -> None:
    """Record that the current run used the work ``key`` (a key of :data:`BIBTEX`)."""
    if key not in BIBTEX:
        raise KeyError(f"unknown citation key {key!r}; known: {sorted(BIBTEX)}")
    _used.setdefault(key, None)


def reset() -> None:
    """Forget what has been registered (useful between independent runs)."""
    _used.clear()


def citations(*, bibtex: bool = True) -> list[str]:
    """The works the current process relied on, in the order first used.

    Parameters
    ----------
    bibtex : bool, keyword-only
        Return full BibTeX entries (default) or just the keys.

    Examples
    --------
    >>> import mudrft
    >>> _ = mudrft.paper_parameters(0.25)
    >>> "chen2026mud" in mudrft.citations(bibtex=False)
    True
    """
    keys = list(_used)
    return [BIBTEX[k] for k in keys] if bibtex else keys
