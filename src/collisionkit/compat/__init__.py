"""Drop-in interfaces that match other packages' collision APIs."""
