"""Shipped data of tirefric: compounds, road surfaces, tires, grid specs and study specs.

Installed as the data package ``tirefric_models``; each file states where its numbers come from.
"""
