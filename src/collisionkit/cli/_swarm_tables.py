"""The ``swarm`` command's tables: transport coefficients, Townsend coefficients and speed, field components."""

from __future__ import annotations

from ._common import print_table


def _with_error(value, error, digits=4):
    """``value ± error``; 0 alone for an exact zero (no reaction), "-" for NaN (no SST root, an older result)."""
    if value != value:
        return "-"
    return "0" if value == 0.0 and error == 0.0 else f"{value:.{digits}g} ± {error:.2g}"


def _swarm_row(result, magnetic: bool = False):
    """A row of the transport table; with B, N D_T (the mean of two different directions across E) gives way to the
    tensor of the components table."""
    transverse = ("see below" if magnetic else
                  f"{result.diffusion_T_N:.4g} ± {result.diffusion_T_N_error:.2g}")
    return (f"{result.reduced_field:g}", f"{result.mean_energy:.5g} ± {result.mean_energy_error:.2g}",
            f"{-result.drift_velocity_bulk[2]:.5g} ± {result.drift_velocity_bulk_error[2]:.2g}",
            f"{result.diffusion_L_N:.4g} ± {result.diffusion_L_N_error:.2g}", transverse)


def _rate_row(result):
    """A row of the Townsend table: alpha/N, eta/N and the run's speed."""
    return (f"{result.reduced_field:g}", _with_error(result.alpha_N, result.alpha_N_error),
            _with_error(result.eta_N, result.eta_N_error), f"{result.collisions_per_second:.3g}")


def print_swarm_tables(results, magnetic: bool, oscillating: bool, angle: float) -> None:
    """The results as tables that fit 80 columns (a terminal's default, and a file's): transport coefficients, then
    Townsend coefficients and speed, then (with B or an oscillating field) the components.

    Each cell holds words of at most about ten characters ("5.821e+23", "±"), so a narrow console wraps a cell
    at its spaces instead of cutting a number; eight columns in one table did not fit (a number or a header
    ended in "…").
    """
    print_table("swarm transport (W along -z for electrons)",
                ("E/N (Td)", "mean energy (eV)", "bulk W (m/s)", "N D_L (1/m/s)", "N D_T (1/m/s)"),
                [_swarm_row(r, magnetic) for r in results])
    print_table("steady-state Townsend coefficients (SST) and the run's speed",
                ("E/N (Td)", "alpha/N (m^2)", "eta/N (m^2)", "collisions/s"), [_rate_row(r) for r in results])
    if magnetic or oscillating:
        what = "cycle averages, " if oscillating else ""
        print_table(f"drift and diffusion components ({what}E along z, B at {angle:g} deg in y-z)",
                    ("E/N (Td)", "quantity", "x / xx / yz", "y / yy / xy", "z / zz / xz"), _field_rows(results))


def _field_rows(results):
    """Rows of the drift and diffusion components that matter in a magnetic or oscillating field (frame: E along
    z, B in the y-z plane; cycle averages for an oscillating field), each with its error: per E/N one row per
    quantity, three components a row."""
    rows = []
    for r in results:
        d, d_error = r.diffusion_N_bulk, r.diffusion_N_bulk_error
        quantities = (
            ("W bulk (m/s)", r.drift_velocity_bulk, r.drift_velocity_bulk_error),
            ("W flux (m/s)", r.drift_velocity_flux, r.drift_velocity_flux_error),
            ("N D bulk, diagonal (1/m/s)", [d[k, k] for k in range(3)], [d_error[k, k] for k in range(3)]),
            ("N D bulk, off-diagonal (1/m/s)", [d[i, j] for i, j in ((1, 2), (0, 1), (0, 2))],
             [d_error[i, j] for i, j in ((1, 2), (0, 1), (0, 2))]),
        )
        for name, values, errors in quantities:
            rows.append((f"{r.reduced_field:g}", name, *(f"{v:.4g} ± {e:.2g}" for v, e in zip(values, errors))))
    return rows
