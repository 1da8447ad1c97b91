import nbformat as nbf

nb = nbf.v4.new_notebook()
md, code = nbf.v4.new_markdown_cell, nbf.v4.new_code_cell
nb.cells = [
    md("""# Reproducing "Learning Humanoid Robot Motions through Deep Neural Networks" in MuJoCo

This notebook runs the study end to end with `mimic`: it records our keyframe kick and the
other team's walk (observed only through joint angles), trains the study's network on both,
runs the kick and walk trials of the originals and the learned copies under the same seeds,
and shows the study's three tables next to ours, plus the joint curves (original vs learned).

Set `MIMIC_PAPER_MINUTES` (simulated minutes per trial and variant) to 30 for the full run;
the default here is small so that the notebook runs in a minute or two."""),
    code("""import os
from pathlib import Path

%matplotlib inline
import matplotlib.pyplot as plt

from mimic.pipeline import reproduce_paper

MINUTES = float(os.environ.get("MIMIC_PAPER_MINUTES", "1"))
OUT = Path(os.environ.get("MIMIC_PAPER_OUT", "out/paper"))
result = reproduce_paper(OUT, minutes=MINUTES, seed=0, say=print)"""),
    md("## Table 1: the network and its fit (mean absolute error over the 22 joints, radians)"),
    code("result.network"),
    md("## Table 2: kick trial (success: the ball travels more than 2 m)"),
    code("result.kick"),
    md("## Table 3: forward walk trial (own goal line to centre line, 15 m)"),
    code("result.walk"),
    md("## Joint curves: original vs learned"),
    code("""from mimic.model.model_file import load_model
from mimic.recording.reader import read_joint_table

def plot_motion(recording, model, joints, title):
    table = read_joint_table(recording, None)
    learned = load_model(model).predict(table["time_s"].to_numpy())
    names = load_model(model).joint_names
    fig, axes = plt.subplots(1, len(joints), figsize=(4 * len(joints), 3), sharex=True)
    for ax, joint in zip(axes, joints):
        ax.plot(table["time_s"], table[joint], label="original", lw=2)
        ax.plot(table["time_s"], learned[:, names.index(joint)], "--", label="learned")
        ax.set_title(joint)
        ax.set_xlabel("time [s]")
    axes[0].set_ylabel("angle [rad]")
    axes[0].legend()
    fig.suptitle(title)
    fig.tight_layout()
    return fig

legs = ["right_hip_pitch", "right_knee_pitch", "right_ankle_pitch", "left_hip_roll"]
plot_motion(OUT / "kick_right.mcap", OUT / "kick_right.mimic", legs, "our kick");
plot_motion(OUT / "other_team_walk.mcap", OUT / "other_team_walk.mimic", legs,
            "the other team's walk (one period)");"""),
]
nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
nbf.write(nb, "notebooks/reproduce_paper.ipynb")
