"""Brake geometry definitions (TOML) shipped with brakewear as package data."""
