import imageio.v3 as iio

from eigengait.optimize.run import write_plots


def test_violation_plot_marks_the_cycle_tolerance(tmp_path):
    rows = [
        {
            "generation": g,
            "outer": g // 10,
            "best_cost": 5.0 / (g + 1),
            "best_violation": 2.0 / (g + 1),
        }
        for g in range(40)
    ]

    def red_pixels(tolerance):
        write_plots(tmp_path, rows, tolerance)
        image = iio.imread(tmp_path / "violation.png")[..., :3].astype(int)
        return ((image[..., 0] > 150) & (image[..., 1] < 90) & (image[..., 2] < 90)).sum()

    assert red_pixels(None) == 0
    assert red_pixels(0.2) > 300  # a line across the axes (and its legend entry)
    assert (tmp_path / "objective.png").exists()
