"""``impactdyn beam``: rotating flexible beam with impact (IMPACTC/IMPACTB)."""

import typer

app = typer.Typer(help="Rotating flexible beam striking a stop (IMPACTC, IMPACTB, ROOTM, INTEG).", no_args_is_help=True)
