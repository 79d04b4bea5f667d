-- Logins for the caretakers' web UI and their browser sessions.
-- Only an argon2id hash of each password and a SHA-256 of each session secret are stored.

create table users (
    name                text primary key not null,  -- lower-case login name
    role                text not null check (role in ('admin', 'caretaker')),
    password_hash       text not null,              -- argon2id PHC string
    created_at          text not null,              -- RFC 3339 UTC
    password_changed_at text not null
) strict;

create table sessions (
    secret_hash text primary key not null,          -- SHA-256 of the cookie's secret, hex
    user_name   text not null references users (name) on delete cascade,
    created_at  text not null,
    expires_at  text not null                       -- fixed at login; never extended
) strict;

create index sessions_user on sessions (user_name);
create index sessions_expiry on sessions (expires_at);
