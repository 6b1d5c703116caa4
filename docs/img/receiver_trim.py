"""Make docs/img/receiver_trim.png (docs/receiver.md): the F-16's level-flight trim at sea level over
airspeed, beside the points of Stevens, Lewis & Johnson (2015) Table 3.6-2, trimmed under the book's
g = 32.17 ft/s^2 as the book does. Run it after a change of the receiver model or its trim:

    .venv/bin/python docs/img/receiver_trim.py
"""

from pathlib import Path

import numpy as np

from hosedrogue.aircraft.model_file import load_model
from hosedrogue.aircraft.published import G_BOOK_FT_S2, TABLE_3_6_2
from hosedrogue.aircraft.trim import trim
from hosedrogue.constants import FT_TO_M
from hosedrogue.studies.receiver_figures import plot_trim_curves


def main(path=Path(__file__).with_suffix(".png")):
    f16 = load_model("f16")
    speeds = np.linspace(130.0, 800.0, 68) * FT_TO_M
    trims = [trim(f16, v, 0.0, gravity=G_BOOK_FT_S2 * FT_TO_M) for v in speeds]
    book = np.array(TABLE_3_6_2) * np.array([FT_TO_M, 1.0, 1.0, 1.0])
    fig = plot_trim_curves(speeds, [t.controls[0] for t in trims], [np.degrees(t.alpha_rad) for t in trims],
                           [t.controls[1] for t in trims], published=book,
                           published_label="Stevens, Lewis & Johnson (2015), Table 3.6-2",
                           title="F-16 (xcg 0.35) in level flight at sea level")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
