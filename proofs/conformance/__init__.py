"""Conformance with the ERA braking-curves tool: its reference frames read and every row computed by the model."""
